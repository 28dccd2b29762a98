#include "common/mesh_arrays.hpp"

namespace engine {

namespace {
template <class T>
size_t cap_bytes(const std::vector<T>& v) { return v.capacity() * sizeof(T); }
}  // namespace

void Nodes::resize(int32_t n) {
  for (auto* v : {&x, &y, &x0, &y0, &vx, &vy, &mass, &mass_phys, &mass_floor, &f_int_x, &f_int_y, &f_visc_x,
                  &f_visc_y, &f_con_x, &f_con_y, &f_coh_x, &f_coh_y, &f_buoy_y, &drag_k,
                  &f_x, &f_y, &f_pre_x, &f_pre_y, &r_x, &r_y, &v_bc_x, &v_bc_y, &f_ref_x, &f_ref_y})
    v->resize(n, 0.0);
  constrained.resize(n, 0);
  sleep.resize(n, 0);
  quiet.resize(n, 0);
}

size_t Nodes::bytes() const {
  size_t b = cap_bytes(constrained) + cap_bytes(sleep) + cap_bytes(quiet);
  for (auto* v : {&x, &y, &x0, &y0, &vx, &vy, &mass, &mass_phys, &mass_floor, &f_int_x, &f_int_y, &f_visc_x,
                  &f_visc_y, &f_con_x, &f_con_y, &f_coh_x, &f_coh_y, &f_buoy_y, &drag_k,
                  &f_x, &f_y, &f_pre_x, &f_pre_y, &r_x, &r_y, &v_bc_x, &v_bc_y, &f_ref_x, &f_ref_y})
    b += cap_bytes(*v);
  return b;
}

void Triangles::resize(int32_t m) {
  node.resize(3 * size_t(m), 0);
  body.resize(m, 0);
  for (auto* v : {&binv00, &binv01, &binv10, &binv11, &area0, &energy}) v->resize(m, 0.0);
  stress.resize(3 * size_t(m), 0.0);
  corner_load.resize(3 * CornerLoad::stride * size_t(m), 0.0);
}

size_t Triangles::bytes() const {
  size_t b = cap_bytes(node) + cap_bytes(body);
  for (auto* v : {&binv00, &binv01, &binv10, &binv11, &area0, &energy, &stress, &corner_load})
    b += cap_bytes(*v);
  return b;
}

}  // namespace engine
