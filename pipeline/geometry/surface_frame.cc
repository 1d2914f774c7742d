#include "pipeline/geometry/surface_frame.h"

#include <cmath>
#include <glm/geometric.hpp>

namespace texsim {

namespace {

bool finite_nonzero(const glm::dvec3& v) {
  const double l = glm::length(v);
  return std::isfinite(l) && l > 1e-300;
}

}  // namespace

SurfaceFrame::SurfaceFrame(const Scene& scene, const ScenePrimitive& prim) {
  const Camera& cam = scene.camera;
  fwd_ = glm::normalize(cam.look_at - cam.position);
  right_ = glm::normalize(glm::cross(fwd_, cam.up));
  down_ = -glm::cross(right_, fwd_);
  focal_ = static_cast<double>(cam.focal_px());
  cx_ = static_cast<double>(cam.cx());
  cy_ = static_cast<double>(cam.cy());
  ortho_ = cam.orthographic;
  // (u, v) = uv0 + a·uvA + b·uvB, P = P0 + a·eA + b·eB: dP/du and dP/dv through the inverse
  // of the 2×2 map [uvA uvB].
  const glm::dvec2 ua = prim.uv_edge_u, ub = prim.uv_edge_v;
  const double det = ua.x * ub.y - ub.x * ua.y;
  glm::dvec3 n = glm::cross(prim.edge_u, prim.edge_v);
  if (!(std::fabs(det) > 1e-300) || !finite_nonzero(n)) {
    degenerate_ = true;
    return;
  }
  // [a b]ᵀ = M⁻¹ [u v]ᵀ with M⁻¹ = [ub.y −ub.x; −ua.y ua.x] / det.
  const glm::dvec3 dpdu = (prim.edge_u * ub.y - prim.edge_v * ua.y) / det;
  const glm::dvec3 dpdv = (-prim.edge_u * ub.x + prim.edge_v * ua.x) / det;
  n = glm::normalize(n);
  // The side the camera sees: towards the eye from the plane's origin (perspective), against
  // the view direction (orthographic).
  const glm::dvec3 towards_eye = ortho_ ? -fwd_ : cam.position - prim.origin;
  if (glm::dot(n, towards_eye) < 0) n = -n;
  n_ = n;
  u_len_ = glm::length(dpdu);
  v_len_ = glm::length(dpdv);
  const glm::dvec3 t = dpdu - n * glm::dot(n, dpdu);
  if (!finite_nonzero(t)) {
    degenerate_ = true;
    return;
  }
  t_ = glm::normalize(t);
  // B: the in-plane direction of dP/dv made orthogonal to T (it keeps dP/dv's side of T).
  const glm::dvec3 b = dpdv - n * glm::dot(n, dpdv) - t_ * glm::dot(t_, dpdv);
  b_ = finite_nonzero(b) ? glm::normalize(b) : glm::cross(n_, t_);
}

glm::dvec3 SurfaceFrame::view(double x, double y) const {
  if (ortho_) return -fwd_;
  const glm::dvec3 d = fwd_ + right_ * ((x - cx_) / focal_) + down_ * ((y - cy_) / focal_);
  return -glm::normalize(d);
}

glm::dvec3 SurfaceFrame::to_tangent(const glm::dvec3& w) const {
  return {glm::dot(w, t_), glm::dot(w, b_), glm::dot(w, n_)};
}

}  // namespace texsim
