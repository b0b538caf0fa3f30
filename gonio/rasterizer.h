// A software rasterizer for the image-based acquisition (DESIGN §5, sample 3): a triangle mesh
// seen by a perspective camera (GLM matrices), z-buffered, with vertex normals and positions
// interpolated perspective-correctly (attributes divided by clip w, interpolated linearly in
// screen space, then divided by the interpolated 1/w: Heckbert & Moreton, "Interpolation for
// polygon texture mapping and shading", 1991).
#pragma once

#include <glm/glm.hpp>
#include <vector>

namespace brdf::gonio {

struct TriangleMesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;    // one per position
  std::vector<glm::uvec3> triangles;  // indices into positions
};

// A UV sphere of unit radius about the origin: `segments` around the equator, segments/2 from
// pole to pole; vertex normals are the exact sphere normals.
TriangleMesh MakeUvSphere(int segments);

struct PinholeCamera {
  glm::dvec3 eye{0, 0, 10}, target{0, 0, 0}, up{0, 1, 0};
  double vertical_fov = 0.2;  // radians
  int resolution = 128;       // square image

  glm::dmat4 ViewProjection() const;

  // The camera's orthonormal axes, with the half-height of the image plane at distance 1.
  struct Basis {
    glm::dvec3 forward, right, up;
    double tangent = 0;
  };
  Basis MakeBasis() const;
  // Unit world-space direction of the ray through the centre of pixel (x, y) (row 0 on top).
  glm::dvec3 PixelRay(const Basis& basis, int x, int y) const;
  glm::dvec3 PixelRay(int x, int y) const { return PixelRay(MakeBasis(), x, y); }
};

// What each pixel sees: the nearest surface's interpolated normal (unit) and position.
struct GBuffer {
  int resolution = 0;
  std::vector<double> depth;  // NDC depth, +infinity where nothing was drawn
  std::vector<glm::dvec3> normal;
  std::vector<glm::dvec3> position;
  bool covered(size_t pixel) const { return depth[pixel] < 2.0; }
};

// Rasterizes `mesh` (back faces culled by their vertex normals). Bands of rows run in parallel;
// each band draws the triangles in mesh order, so the image does not depend on threads.
GBuffer Rasterize(const TriangleMesh& mesh, const PinholeCamera& camera);

}  // namespace brdf::gonio
