#include "gonio/rasterizer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

#include "core/angles.h"

namespace brdf::gonio {
namespace {

constexpr int kRowsPerBand = 16;

struct ScreenVertex {
  double x, y;       // pixel coordinates, y down
  double depth;      // NDC z
  double inverse_w;  // 1 / clip w
};

double Edge(const ScreenVertex& a, const ScreenVertex& b, double x, double y) {
  return (x - a.x) * (b.y - a.y) - (y - a.y) * (b.x - a.x);
}

}  // namespace

TriangleMesh MakeUvSphere(int segments) {
  TriangleMesh mesh;
  const int rings = std::max(2, segments / 2);
  for (int r = 0; r <= rings; ++r) {
    const double theta = kPi * r / rings;
    for (int s = 0; s <= segments; ++s) {
      const double phi = 2 * kPi * s / segments;
      const glm::dvec3 p(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         std::cos(theta));
      mesh.positions.push_back(p);
      mesh.normals.push_back(p);
    }
  }
  const unsigned row = segments + 1;
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const unsigned a = r * row + s, b = a + 1, c = a + row, d = c + 1;
      if (r > 0) mesh.triangles.emplace_back(a, c, b);  // the pole rows degenerate to one
      if (r + 1 < rings) mesh.triangles.emplace_back(b, c, d);
    }
  }
  return mesh;
}

glm::dmat4 PinholeCamera::ViewProjection() const {
  const double near = 0.01 * glm::length(eye - target);
  return glm::perspective(vertical_fov, 1.0, near, 100.0 * glm::length(eye - target)) *
         glm::lookAt(eye, target, up);
}

PinholeCamera::Basis PinholeCamera::MakeBasis() const {
  Basis basis;
  basis.forward = glm::normalize(target - eye);
  basis.right = glm::normalize(glm::cross(basis.forward, up));
  basis.up = glm::cross(basis.right, basis.forward);
  basis.tangent = std::tan(0.5 * vertical_fov);
  return basis;
}

glm::dvec3 PinholeCamera::PixelRay(const Basis& basis, int x, int y) const {
  const double ndc_x = 2.0 * (x + 0.5) / resolution - 1.0;
  const double ndc_y = 1.0 - 2.0 * (y + 0.5) / resolution;
  return glm::normalize(basis.forward + ndc_x * basis.tangent * basis.right +
                        ndc_y * basis.tangent * basis.up);
}

GBuffer Rasterize(const TriangleMesh& mesh, const PinholeCamera& camera) {
  const int n = camera.resolution;
  GBuffer buffer;
  buffer.resolution = n;
  buffer.depth.assign(size_t(n) * n, std::numeric_limits<double>::infinity());
  buffer.normal.assign(size_t(n) * n, glm::dvec3(0));
  buffer.position.assign(size_t(n) * n, glm::dvec3(0));
  const glm::dmat4 view_projection = camera.ViewProjection();
  std::vector<ScreenVertex> screen(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::dvec4 clip = view_projection * glm::dvec4(mesh.positions[v], 1.0);
    const double inverse_w = 1.0 / clip.w;
    screen[v] = {(clip.x * inverse_w * 0.5 + 0.5) * n, (0.5 - clip.y * inverse_w * 0.5) * n,
                 clip.z * inverse_w, inverse_w};
  }
  // Front-facing triangles only: at least one vertex normal turned toward the eye.
  std::vector<unsigned> visible;
  for (unsigned t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (glm::dot(mesh.normals[tri[k]], camera.eye - mesh.positions[tri[k]]) > 0) {
        visible.push_back(t);
        break;
      }
    }
  }
  // Bin the triangles by the bands of rows their bounding boxes touch, in mesh order.
  const int bands = (n + kRowsPerBand - 1) / kRowsPerBand;
  std::vector<std::vector<unsigned>> band_triangles(bands);
  for (unsigned t : visible) {
    const glm::uvec3& tri = mesh.triangles[t];
    const double low = std::min({screen[tri[0]].y, screen[tri[1]].y, screen[tri[2]].y});
    const double high = std::max({screen[tri[0]].y, screen[tri[1]].y, screen[tri[2]].y});
    const int first = std::max(0, static_cast<int>(std::floor(low)) / kRowsPerBand);
    const int last = std::min(bands - 1, static_cast<int>(std::ceil(high)) / kRowsPerBand);
    for (int band = first; band <= last; ++band) band_triangles[band].push_back(t);
  }
  tbb::parallel_for(0, bands, [&](int band) {
    const int row_begin = band * kRowsPerBand, row_end = std::min(n, row_begin + kRowsPerBand);
    for (unsigned t : band_triangles[band]) {
      const glm::uvec3& tri = mesh.triangles[t];
      const ScreenVertex &a = screen[tri[0]], &b = screen[tri[1]], &c = screen[tri[2]];
      const double area = Edge(a, b, c.x, c.y);
      if (std::abs(area) < 1e-12) continue;
      const int y0 = std::max(row_begin, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
      const int y1 = std::min(row_end - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
      const int x1 = std::min(n - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const double px = x + 0.5, py = y + 0.5;
          // Screen-space barycentrics; dividing by the signed area accepts either winding.
          const double w_a = Edge(b, c, px, py) / area, w_b = Edge(c, a, px, py) / area;
          const double w_c = 1.0 - w_a - w_b;
          if (w_a < 0 || w_b < 0 || w_c < 0) continue;
          const double depth = w_a * a.depth + w_b * b.depth + w_c * c.depth;
          const size_t pixel = size_t(y) * n + x;
          if (depth >= buffer.depth[pixel]) continue;
          buffer.depth[pixel] = depth;
          // Perspective-correct weights: linear in screen space for attribute/w and 1/w.
          const double p_a = w_a * a.inverse_w, p_b = w_b * b.inverse_w, p_c = w_c * c.inverse_w;
          const double inverse_sum = 1.0 / (p_a + p_b + p_c);
          buffer.normal[pixel] =
              glm::normalize((p_a * mesh.normals[tri[0]] + p_b * mesh.normals[tri[1]] +
                              p_c * mesh.normals[tri[2]]) *
                             inverse_sum);
          buffer.position[pixel] = (p_a * mesh.positions[tri[0]] + p_b * mesh.positions[tri[1]] +
                                    p_c * mesh.positions[tri[2]]) *
                                   inverse_sum;
        }
      }
    }
  });
  return buffer;
}

}  // namespace brdf::gonio
