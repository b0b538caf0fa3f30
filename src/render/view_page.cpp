#include "render/view_page.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/angles.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "energy/albedo_source.h"
#include "models/model_source.h"
#include "render/material.h"
#include "render/view_assets.h"

namespace brdf {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Float32 little-endian values as base64: a quarter of the size of the same numbers in JSON.
std::string Base64Floats(const std::vector<float>& values) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes(values.size() * 4, '\0');
  std::memcpy(bytes.data(), values.data(), bytes.size());
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t left = bytes.size() - i;
    uint32_t word = static_cast<uint8_t>(bytes[i]) << 16;
    if (left > 1) word |= static_cast<uint8_t>(bytes[i + 1]) << 8;
    if (left > 2) word |= static_cast<uint8_t>(bytes[i + 2]);
    out += kAlphabet[(word >> 18) & 63];
    out += kAlphabet[(word >> 12) & 63];
    out += left > 1 ? kAlphabet[(word >> 6) & 63] : '=';
    out += left > 2 ? kAlphabet[word & 63] : '=';
  }
  return out;
}

void Append(const Rgb& value, std::vector<float>* out) {
  for (int c = 0; c < 3; ++c) out->push_back(static_cast<float>(value[c]));
}

std::vector<double> Steps(double first, double last, double step) {
  std::vector<double> values;
  for (double v = first; v <= last + 1e-9; v += step) values.push_back(v);
  return values;
}

nlohmann::json SourceJson(const std::string& source, const ViewGrid& grid) {
  const bool model = IsModelSpec(source);
  const std::unique_ptr<Material> material = LoadMaterial(source);
  nlohmann::json json;
  json["name"] = std::filesystem::path(source).filename().string();
  if (model && !IsFitReportPath(source)) json["name"] = source;
  json["describe"] = material->Describe();
  json["measured"] = !model;

  // Plane of incidence: wi at phi = 0, wo in the same plane, positive angles mirrored
  // (the specular direction of theta_i is theta_o = +theta_i).
  const std::vector<double> incidence = Steps(0, grid.incidence_max_deg, grid.incidence_step_deg);
  const double outgoing_max = 90 - grid.outgoing_step_deg;
  const std::vector<double> outgoing =
      Steps(-outgoing_max, outgoing_max + 1e-9, grid.outgoing_step_deg);
  std::vector<float> plane;
  for (double ti : incidence) {
    const Vec3 wi(std::sin(ti * kDeg), 0, std::cos(ti * kDeg));
    for (double to : outgoing) {
      const Vec3 wo(-std::sin(to * kDeg), 0, std::cos(to * kDeg));
      Append(material->Eval(wi, wo), &plane);
    }
  }
  json["plane"] = {
      {"incidence_deg", incidence}, {"outgoing_deg", outgoing}, {"rgb", Base64Floats(plane)}};

  // The half/difference table at cell centres (see ViewGrid).
  std::vector<float> table;
  std::vector<double> theta_h, theta_d, phi_d;
  for (int i = 0; i < grid.theta_h_cells; ++i) {
    const double u = (i + 0.5) / grid.theta_h_cells;
    theta_h.push_back(u * u * 90);
  }
  for (int i = 0; i < grid.theta_d_cells; ++i)
    theta_d.push_back((i + 0.5) * 90 / grid.theta_d_cells);
  for (int i = 0; i < grid.phi_d_cells; ++i) phi_d.push_back((i + 0.5) * 180 / grid.phi_d_cells);
  for (double th : theta_h) {
    for (double td : theta_d) {
      for (double pd : phi_d) {
        HalfDiff hd;
        hd.theta_h = th * kDeg;
        hd.theta_d = td * kDeg;
        hd.phi_d = pd * kDeg;
        Vec3 wi, wo;
        FromHalfDiff(hd, &wi, &wo);
        if (wi.z() <= 0 || wo.z() <= 0) {
          Append(Rgb::Zero(), &table);  // below the horizon: no light is reflected there
        } else {
          Append(material->Eval(wi, wo), &table);
        }
      }
    }
  }
  json["table"] = {{"theta_h_deg", theta_h},
                   {"theta_d_deg", theta_d},
                   {"phi_d_deg", phi_d},
                   {"rgb", Base64Floats(table)}};

  AlbedoOptions albedo_options;
  albedo_options.theta_steps = grid.albedo_steps;
  const AlbedoCurve curve = SourceAlbedoCurve(source, albedo_options);
  const EnergyVerdict verdict = curve.verdict();
  std::vector<double> albedo_theta;
  std::vector<float> albedo;
  for (const AlbedoPoint& point : curve.points) {
    albedo_theta.push_back(point.theta_deg);
    Append(point.estimate.albedo, &albedo);
  }
  json["albedo"] = {{"theta_deg", albedo_theta},
                    {"rgb", Base64Floats(albedo)},
                    {"conserving", verdict.conservation == Conservation::kConserving},
                    {"verdict", verdict.Text()}};
  return json;
}

void ReplaceOnce(std::string* text, const std::string& marker, std::string_view with) {
  const size_t at = text->find(marker);
  if (at == std::string::npos) throw ComputeError("view page template lacks " + marker);
  text->replace(at, marker.size(), with);
}

}  // namespace

std::string ViewPageHtml(const std::vector<std::string>& sources, const ViewGrid& grid) {
  if (sources.empty()) throw UsageError("brdf view: no source given");
  nlohmann::json data;
  data["sources"] = nlohmann::json::array();
  for (const std::string& source : sources) data["sources"].push_back(SourceJson(source, grid));
  std::string json = data.dump();
  // Inside a <script> element, "</" could close it.
  for (size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 3)) {
    json.replace(at, 2, "<\\/");
  }
  std::string page(ViewTemplate());
  ReplaceOnce(&page, "@BRDF_DATA@", json);
  ReplaceOnce(&page, "@THREE_LICENSE@", ThreeLicense());
  ReplaceOnce(&page, "@THREE_CORE@", ThreeCore());
  ReplaceOnce(&page, "@THREE_MODULE@", ThreeModule());
  return page;
}

void WriteViewPage(const std::vector<std::string>& sources, const std::string& path,
                   const ViewGrid& grid) {
  const std::string page = ViewPageHtml(sources, grid);
  WriteFileAtomically(path, [&](std::ostream& out) { out << page; });
}

}  // namespace brdf
