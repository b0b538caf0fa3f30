// brdf batch FILE... --model M|auto [--loss ...] [--robust ...] [--out DIR] [--json]: fits many
// measurement files (DESIGN §3) and writes each fit report (DIR/<name>.json, the report of
// `brdf fit --out`) and one table, DIR/table.csv, one row per input in command-line order.
//
// Under mpirun the files are dealt across the ranks, largest first (DESIGN §11); rank 0 writes
// every report as it arrives and the table at the end, so the outputs are identical for any
// rank count. A file that cannot be read or fitted fails alone: its report is not written, its
// row says why, the others are still fitted and written (each report whole or not at all), and
// the job exits 2 (bad input; 3 when only fits failed or did not converge).
#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "cli/commands.h"
#include "cli/fit_options.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/parallel_ranks.h"
#include "core/progress.h"
#include "core/text.h"
#include "fitters/fit.h"
#include "fitters/report.h"
#include "fitters/select.h"
#include "io/formats.h"

namespace brdf::cli {
namespace {

namespace fs = std::filesystem;

// The table's columns, in order. Numbers are written as the shortest text that reads back to
// the same double; a field holding a comma or a quote is quoted (RFC 4180).
const std::vector<std::string>& TableColumns() {
  static const std::vector<std::string> columns = {
      "file",   "report",   "status",     "model",        "converged",    "params",
      "rmse",   "log_rmse", "cosine_l2",  "max_albedo_r", "max_albedo_g", "max_albedo_b",
      "energy", "samples",  "iterations", "time_s",       "error"};
  return columns;
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

std::string JsonField(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
  if (value.is_number_float()) return FormatNumber(value.get<double>());
  if (value.is_null()) return "";
  return value.dump();
}

// Report file names: the input's name without its extension, or with it where two inputs
// share a stem (cayman.astm and cayman.brdf). Inputs that still collide are refused.
std::vector<std::string> ReportNames(const std::vector<std::string>& files) {
  std::map<std::string, int> stems, names;
  for (const std::string& file : files) {
    ++stems[fs::path(file).stem().string()];
    ++names[fs::path(file).filename().string()];
  }
  std::vector<std::string> reports;
  std::map<std::string, std::string> taken;
  for (const std::string& file : files) {
    const fs::path path(file);
    const std::string stem = path.stem().string();
    const std::string name = (stems[stem] > 1 ? path.filename().string() : stem) + ".json";
    const auto [previous, fresh] = taken.emplace(name, file);
    if (!fresh) {
      throw UsageError("'" + previous->second + "' and '" + file + "' would both write " + name +
                       ": give each input a distinct file name");
    }
    reports.push_back(name);
  }
  return reports;
}

// The inputs with each directory replaced by its files that a reader recognises, sorted by name
// (hidden files and subdirectories left out); the files passed over are named in `skipped`.
std::vector<std::string> ExpandDirectories(const std::vector<std::string>& inputs,
                                           std::vector<std::string>* skipped) {
  std::vector<std::string> files;
  for (const std::string& input : inputs) {
    std::error_code error;
    if (!fs::is_directory(input, error)) {
      files.push_back(input);
      continue;
    }
    std::vector<std::string> entries;
    for (const fs::directory_entry& entry : fs::directory_iterator(input, error)) {
      const std::string name = entry.path().filename().string();
      if (name.empty() || name[0] == '.' || !entry.is_regular_file()) continue;
      entries.push_back(entry.path().string());
    }
    if (error) throw InputError(input, "cannot list the directory: " + error.message());
    std::sort(entries.begin(), entries.end());
    size_t readable = 0;
    for (const std::string& entry : entries) {
      try {
        DetectFormat(entry);
        files.push_back(entry);
        ++readable;
      } catch (const InputError&) {
        skipped->push_back(entry);
      }
    }
    if (readable == 0)
      throw InputError(input, "no file in this directory is in a format brdf reads");
  }
  return files;
}

struct BatchOptions {
  std::vector<std::string> files;
  FitArguments fit;
  std::string out, concurrency = "files";
  int threads = 0;
  bool json = false, quiet = false;
};

// One file: read, fit, report. The result is JSON text: {"report": ...} or, for a file that
// failed, {"error": message, "exit_status": 2|3}. Nothing in it depends on rank or thread.
std::string FitOneFile(const BatchOptions& options, const fitters::FitOptions& fit_options,
                       const std::string& path) {
  nlohmann::json result;
  try {
    const Measurement measurement = ReadForFit(path, options.fit);
    const fitters::ModelFit model_fit =
        fitters::FitModelOrAuto(measurement, options.fit.model, fit_options);
    result["report"] = fitters::FitReportJson(model_fit.fit, path, model_fit.selection_or_null());
  } catch (const ComputeError& error) {
    result["error"] = error.what();
    result["exit_status"] = 3;
  } catch (const Error& error) {
    result["error"] = error.what();
    result["exit_status"] = 2;
  }
  return result.dump();
}

// The table row of one file's result, typed (numbers, booleans, text; null where empty).
std::vector<nlohmann::json> TableRow(const std::string& file, const std::string& report_name,
                                     const nlohmann::json& result) {
  std::vector<nlohmann::json> row(TableColumns().size());
  row[0] = file;
  if (result.contains("error")) {
    row[2] = "error";
    row[16] = result["error"];
    return row;
  }
  const nlohmann::json& report = result["report"];
  row[1] = report_name;
  row[2] = report["converged"].get<bool>() ? "ok" : "not-converged";
  row[3] = report["model"];
  row[4] = report["converged"];
  row[5] = report["model_string"];
  row[6] = report["metrics"]["rmse"];
  row[7] = report["metrics"]["log_rmse"];
  row[8] = report["metrics"]["cosine_l2"];
  for (int c = 0; c < 3; ++c) row[9 + c] = report["energy"]["max_albedo"][c];
  row[12] = report["energy"]["verdict"];
  row[13] = report["samples"];
  row[14] = report["iterations"];
  row[15] = report["time_s"];
  return row;
}

void WriteTable(std::ostream& out, const std::vector<std::vector<nlohmann::json>>& rows) {
  const std::vector<std::string>& columns = TableColumns();
  for (size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c];
  out << "\n";
  for (const std::vector<nlohmann::json>& row : rows) {
    for (size_t c = 0; c < row.size(); ++c) out << (c ? "," : "") << CsvField(JsonField(row[c]));
    out << "\n";
  }
}

}  // namespace

Command AddBatchCommand(CLI::App& parent) {
  auto options = std::make_shared<BatchOptions>();
  CLI::App* app = parent.add_subcommand(
      "batch", "Fit many measurement files: one fit report per file and one CSV table");
  app->add_option("FILE", options->files,
                  "measurement files (any format brdf info reads), or directories: their files in "
                  "a format brdf reads, sorted by name")
      ->required();
  AddFitOptions(app, &options->fit);
  app->add_option("--threads", options->threads,
                  "worker threads per process (0: all cores); the outputs do not depend on it")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  app->add_option("--concurrency", options->concurrency,
                  "files: several files at once, each fit on one thread; fit: one file at a "
                  "time, each fit on every thread (the outputs are the same)")
      ->capture_default_str()
      ->check(CLI::IsMember({"files", "fit"}));
  app->add_option("--out", options->out,
                  "directory for the reports (<name>.json, as brdf fit --out writes) and "
                  "table.csv; created if missing. Without it nothing is written");
  app->add_flag("--json", options->json,
                "print the table as JSON (an array of rows keyed by column) instead of CSV");
  app->add_flag("--quiet", options->quiet, "no progress bar on stderr");
  app->footer(
      "table.csv columns: file, report, status (ok, not-converged or error), model, converged, "
      "params (model string), rmse, log_rmse, cosine_l2, max_albedo_r/g/b, energy (conserving, not "
      "conserving or undecided), samples, "
      "iterations, time_s (wall clock; the only column that changes between runs), error. Rows "
      "follow the order of FILE. A file that fails is reported on stderr and in its row; the "
      "other files are still fitted and written; exit status 2 if an input was bad, else 3 if a "
      "fit failed or did not converge. Under mpirun the files are dealt across the ranks, "
      "largest first, and rank 0 writes every output.");

  return {app,
          [options]() {
            // Several files at once: one thread per fit keeps the cores busy without nesting.
            const bool files_at_once = options->concurrency == "files";
            const fitters::FitOptions fit_options =
                options->fit.ToFitOptions(files_at_once ? 1 : options->threads);
            options->fit.ToReadOptions();  // a bad illuminant fails before any file is read
            std::vector<std::string> skipped;
            options->files = ExpandDirectories(options->files, &skipped);
            if (!skipped.empty() && !options->quiet && ranks::IsRoot()) {
              std::cerr << "brdf batch: skipped " << skipped.size()
                        << " files in no format brdf reads:";
              for (const std::string& file : skipped) std::cerr << " " << file;
              std::cerr << "\n";
            }
            const std::vector<std::string> report_names = ReportNames(options->files);
            if (!options->out.empty() && ranks::IsRoot()) {
              std::error_code error;
              fs::create_directories(options->out, error);
              if (error) {
                throw OutputError(options->out,
                                  "cannot create the output directory: " + error.message());
              }
            }
            std::optional<tbb::global_control> thread_limit;
            if (options->threads > 0) {
              thread_limit.emplace(tbb::global_control::max_allowed_parallelism,
                                   static_cast<size_t>(options->threads));
            }

            // Largest first: file size stands for the fit's cost (samples fitted).
            std::vector<double> costs;
            for (const std::string& file : options->files) {
              std::error_code error;
              const auto size = fs::file_size(file, error);
              costs.push_back(error ? 0.0 : static_cast<double>(size));
            }
            std::vector<std::vector<nlohmann::json>> rows(options->files.size());
            int worst = 0, failed = 0;
            Progress progress("fitting", static_cast<int64_t>(options->files.size()),
                              options->quiet || !ranks::IsRoot());
            ranks::DistributeOptions distribute;
            distribute.items_in_parallel = files_at_once;
            ranks::Distribute(
                ranks::LargestFirst(costs), []() {},
                [&](size_t k) { return FitOneFile(*options, fit_options, options->files[k]); },
                [&](size_t k, int rank, std::string&& text) {
                  const nlohmann::json result = nlohmann::json::parse(text);
                  const std::string& file = options->files[k];
                  rows[k] = TableRow(file, report_names[k], result);
                  if (result.contains("error")) {
                    ++failed;
                    const int status = result["exit_status"].get<int>();
                    worst = status == 2 || worst == 2 ? 2 : 3;
                    std::cerr << "brdf batch: " << result["error"].get<std::string>();
                    if (ranks::Size() > 1) std::cerr << " (rank " << rank << ")";
                    std::cerr << "\n";
                  } else {
                    if (!result["report"]["converged"].get<bool>() && worst == 0) worst = 3;
                    if (!options->out.empty()) {
                      WriteFileAtomically(
                          options->out + "/" + report_names[k],
                          [&](std::ostream& out) { out << result["report"].dump(2) << "\n"; });
                    }
                  }
                  progress.Advance();
                },
                distribute);
            if (!ranks::IsRoot()) return 0;  // rank 0 wrote every output

            if (!options->out.empty()) {
              WriteFileAtomically(options->out + "/table.csv",
                                  [&](std::ostream& out) { WriteTable(out, rows); });
            }
            if (options->json) {
              nlohmann::ordered_json table = nlohmann::ordered_json::array();
              for (const std::vector<nlohmann::json>& row : rows) {
                nlohmann::ordered_json entry;
                for (size_t c = 0; c < row.size(); ++c) entry[TableColumns()[c]] = row[c];
                table.push_back(entry);
              }
              std::cout << table.dump(2) << "\n";
            } else {
              WriteTable(std::cout, rows);
            }
            if (failed > 0) {
              std::cerr << "brdf batch: " << failed << " of " << options->files.size()
                        << " files failed\n";
            }
            return worst;
          },
          /*distributed=*/true};
}

}  // namespace brdf::cli
