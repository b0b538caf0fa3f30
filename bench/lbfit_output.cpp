#include "lbfit_output.h"

#include "core/errors.h"
#include "core/format.h"
#include "core/text.h"

namespace brdf::lbfit {
namespace {

const ModelKind* FindKind(std::string_view heading) {
  for (const ModelKind& kind : ModelKinds()) {
    if (kind.heading == heading) return &kind;
  }
  return nullptr;
}

std::string KnownHeadings() {
  std::string list;
  for (const ModelKind& kind : ModelKinds())
    list += (list.empty() ? "[" : ", [") + kind.heading + "]";
  return list;
}

// The expected value count of `name` in `kind`, or 0 when the model has no such parameter.
int ValueCount(const ModelKind& kind, std::string_view name) {
  if (name == "Error") return 1;
  for (const auto& [parameter, count] : kind.parameters) {
    if (parameter == name) return count;
  }
  return 0;
}

// Checks that the block begun at `heading_line` printed every parameter and its error.
void CheckComplete(const std::string& path, int64_t heading_line, const PrintedFit& fit,
                   bool has_error) {
  for (const auto& [parameter, count] : fit.kind->parameters) {
    if (!fit.parameters.count(parameter)) {
      throw ParseError(path, heading_line,
                       "[" + fit.kind->heading + "] has no '" + parameter + "' line");
    }
  }
  if (!has_error) {
    throw ParseError(path, heading_line, "[" + fit.kind->heading + "] has no 'Error' line");
  }
}

}  // namespace

std::vector<PrintedFit> ParseLbfitOutput(const std::string& path, std::string_view text) {
  std::vector<PrintedFit> fits;
  LineReader reader(path, text);
  std::string_view line;
  int64_t heading_line = 0;
  bool has_error = false;
  while (reader.Next(&line)) {
    line = Trim(line);
    if (line.empty()) continue;
    if (line.front() == '[') {
      if (line.back() != ']') reader.Fail("a heading must end with ']'");
      if (!fits.empty()) CheckComplete(path, heading_line, fits.back(), has_error);
      const std::string_view heading = line.substr(1, line.size() - 2);
      const ModelKind* kind = FindKind(heading);
      if (!kind) {
        reader.Fail("unknown lbfit model [" + PrintableText(heading) +
                    "] (known: " + KnownHeadings() + ")");
      }
      for (const PrintedFit& fit : fits) {
        if (fit.kind == kind) reader.Fail("[" + kind->heading + "] printed twice");
      }
      fits.push_back({kind, {}, 0.0});
      heading_line = reader.line_number();
      has_error = false;
      continue;
    }
    if (fits.empty()) reader.Fail("expected a model heading such as [Unreal Engine 4]");
    const size_t colon = line.find(':');
    if (colon == std::string_view::npos) reader.Fail("expected 'Name: value(s)'");
    const std::string name(Trim(line.substr(0, colon)));
    PrintedFit& fit = fits.back();
    const int count = ValueCount(*fit.kind, name);
    if (count == 0) {
      reader.Fail("[" + fit.kind->heading + "] has no parameter '" + PrintableText(name) + "'");
    }
    if (fit.parameters.count(name) || (name == "Error" && has_error)) {
      reader.Fail("'" + name + "' printed twice in [" + fit.kind->heading + "]");
    }
    const std::vector<std::string_view> fields = SplitFields(line.substr(colon + 1), " \t", true);
    if (static_cast<int>(fields.size()) != count) {
      reader.Fail(Format("'%s' needs %d value(s), found %zu", name.c_str(), count, fields.size()));
    }
    std::vector<double> values;
    for (std::string_view field : fields)
      values.push_back(ParseNumber(reader, field, name.c_str()));
    if (name == "Error") {
      fit.lbfit_error = values[0];
      has_error = true;
    } else {
      fit.parameters[name] = values;
    }
  }
  if (fits.empty()) throw InputError(path, "no lbfit model blocks (expected e.g. [Lambertian])");
  CheckComplete(path, heading_line, fits.back(), has_error);
  return fits;
}

std::vector<PrintedFit> ReadLbfitOutput(const std::string& path) {
  return ParseLbfitOutput(path, ReadFileBytes(path, int64_t{1} << 20));
}

}  // namespace brdf::lbfit
