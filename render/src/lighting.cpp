#include "sculpt/render/lighting.hpp"

#include <algorithm>

namespace sculpt::render {

Vec3 light_direction(const Camera& camera, const Lighting& lighting) {
  Vec3 right, up, back;
  camera.basis(right, up, back);
  const Vec3& l = lighting.light_in_camera;
  return normalized(l.x * right + l.y * up + l.z * back);
}

void shade(const RenderModel& model, const Camera& camera, const Lighting& lighting, std::vector<float>& colors) {
  const Vec3 l = light_direction(camera, lighting);
  const std::vector<float>& p = model.positions();
  const std::vector<float>& n = model.normals();
  const std::vector<float>& base = model.colors();
  colors.resize(base.size());
  for (std::size_t i = 0; i < model.size(); ++i) {
    Vec3 normal{n[3 * i], n[3 * i + 1], n[3 * i + 2]};
    const Vec3 to_eye = camera.eye - Vec3{p[3 * i], p[3 * i + 1], p[3 * i + 2]};
    if (dot(normal, to_eye) < 0.0) normal = -normal;
    const double lit = lighting.ambient + lighting.diffuse * std::max(0.0, dot(normal, l));
    for (int c = 0; c < 3; ++c) colors[3 * i + c] = static_cast<float>(base[3 * i + c] * lit);
  }
}

}  // namespace sculpt::render
