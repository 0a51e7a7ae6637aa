#include "sim/scene/Camera.h"

#include <algorithm>
#include <cmath>

namespace sph::scene {

Mat4 identity() {
  Mat4 r;
  r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1;
  return r;
}

Mat4 multiply(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int c = 0; c < 4; ++c) {
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += static_cast<double>(a(row, k)) * b(k, c);
      r.m[static_cast<std::size_t>(4 * c + row)] = static_cast<float>(s);
    }
  }
  return r;
}

Mat4 lookAt(const Vec3& eye, const Vec3& target, const Vec3& up) {
  const Vec3d e = eye.cast<double>();
  const Vec3d f = (target.cast<double>() - e).normalized();
  const Vec3d s = f.cross(up.cast<double>()).normalized();
  const Vec3d u = s.cross(f);
  Mat4 r = identity();
  auto set = [&](int row, int column, double v) {
    r.m[static_cast<std::size_t>(4 * column + row)] = static_cast<float>(v);
  };
  set(0, 0, s.x()), set(0, 1, s.y()), set(0, 2, s.z()), set(0, 3, -s.dot(e));
  set(1, 0, u.x()), set(1, 1, u.y()), set(1, 2, u.z()), set(1, 3, -u.dot(e));
  set(2, 0, -f.x()), set(2, 1, -f.y()), set(2, 2, -f.z()), set(2, 3, f.dot(e));
  return r;
}

Mat4 perspective(float fovYDegrees, float aspect, float near, float far) {
  const double f = 1.0 / std::tan(0.5 * static_cast<double>(fovYDegrees) * M_PI / 180.0);
  const double n = near, fa = far;
  Mat4 r;
  r.m[0] = static_cast<float>(f / aspect);
  r.m[5] = static_cast<float>(f);
  r.m[10] = static_cast<float>((fa + n) / (n - fa));
  r.m[11] = -1;
  r.m[14] = static_cast<float>(2 * fa * n / (n - fa));
  return r;
}

CameraFrame cameraFrame(const CameraDesc& camera, float aspect) {
  CameraFrame f;
  static_cast<CameraBasis&>(f) = cameraBasis(camera);
  f.projView = multiply(perspective(camera.fovYDegrees, aspect, camera.near, camera.far),
                        lookAt(camera.position, camera.target, camera.up));
  return f;
}

CameraDesc cameraAt(const CameraDesc& base, const CameraPath& path, double t) {
  CameraDesc c = base;
  if (path.empty()) return c;
  auto apply = [&](const CameraKey& k) {
    c.position = k.position, c.target = k.target, c.fovYDegrees = k.fovYDegrees;
    return c;
  };
  if (t <= path.front().time) return apply(path.front());
  if (t >= path.back().time) return apply(path.back());
  std::size_t i = 1;
  while (path[i].time < t) ++i;
  const CameraKey &a = path[i - 1], &b = path[i];
  const double s = (t - a.time) / (b.time - a.time);
  const Vec3d eye = (1 - s) * a.position.cast<double>() + s * b.position.cast<double>();
  const Vec3d da = (a.target - a.position).cast<double>(),
              db = (b.target - b.position).cast<double>();
  const double la = da.norm(), lb = db.norm();
  const Vec3d ua = da / la, ub = db / lb;
  const double angle = std::acos(std::clamp(ua.dot(ub), -1.0, 1.0));
  Vec3d dir;
  if (angle < 1e-9) {
    dir = ua;
  } else if (M_PI - angle < 1e-6) {  // opposite directions: no unique turn, jump halfway
    dir = s < 0.5 ? ua : ub;
  } else {
    dir = (std::sin((1 - s) * angle) * ua + std::sin(s * angle) * ub) / std::sin(angle);
  }
  c.position = eye.cast<float>();
  c.target = (eye + ((1 - s) * la + s * lb) * dir.normalized()).cast<float>();
  c.fovYDegrees = static_cast<float>((1 - s) * a.fovYDegrees + s * b.fovYDegrees);
  return c;
}

Frustum::Frustum(const Mat4& m) {
  auto row = [&](int r) { return Eigen::Vector4f(m(r, 0), m(r, 1), m(r, 2), m(r, 3)); };
  const Eigen::Vector4f r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
  planes = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2};
  for (auto& p : planes) p /= p.head<3>().norm();
}

Frustum viewFrustum(const CameraDesc& camera, float aspect, float near, float far) {
  CameraDesc c = camera;
  c.near = near, c.far = far;
  return Frustum(cameraFrame(c, aspect).projView);
}

}  // namespace sph::scene
