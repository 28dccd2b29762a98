// One node's gather (docs/model.md §3): the sums of its corners' loads in
// the fixed order of NodeGather (ascending corner slot), plus gravity and
// drag, written once for both backends (Model::gather_node on the CPU,
// cuda/body_forces.cu per node). A node's sums do not depend on which thread
// or GPU lane takes it, so both backends give the same bits.
#pragma once
#include <cstdint>

#include "common/corner_layout.hpp"
#include "common/host_device.hpp"
#include "common/mesh_arrays.hpp"

namespace engine {

struct GatherArrays {
  const int32_t* start;  // NodeGather
  const int32_t* slot;
  const double* vx;
  const double* vy;
  const double* mass_phys;
  double* f_int_x;
  double* f_int_y;
  double* f_visc_x;
  double* f_visc_y;
  double* f_buoy_y;
  double* drag_k;
  double* f_x;
  double* f_y;
  double* f_coh_x;
  double* f_coh_y;
  bool damping, water, buoyancy, drag;
  double g;  // gravity [m/s²], 0 without
};

// Node i's total of everything but contact, bonds and friction (and its
// parts by origin); zeroes its cohesive force for the bond pass. The corner
// loads are read from `load` (common/corner_layout.hpp).
// The corners are read Batch at a time, all their loads before any is
// added (in slot order, as one at a time: the same sums for any Batch). The
// GPU reads 4 (cuda/body_forces.cu): a lane's corner loads waited for its
// slot, one corner after another. The CPU reads 1: its cores run ahead by
// themselves, and 4 made the elements part ~15 % slower (paper mesh, load
// phase, this project's 2-core machine, 2026-12-01).
template <int Batch = 1, class Corners>
ICERUBBLE_HD void gather_node_loads(const GatherArrays& a, Corners load, int32_t i) {
  double fx = 0.0, fy = 0.0, vx = 0.0, vy = 0.0, fb = 0.0, k = 0.0;
  const int32_t end = a.start[i + 1];
  if constexpr (Batch == 1) {  // the loop as it reads (the batched form with 1 compiled ~3 % slower)
    for (int32_t j = a.start[i]; j < end; ++j) {
      const size_t c = size_t(a.slot[j]);
      fx += load(c, CornerLoad::fx);
      fy += load(c, CornerLoad::fy);
      if (a.damping) {
        vx += load(c, CornerLoad::visc_x);
        vy += load(c, CornerLoad::visc_y);
      }
      if (a.water) {
        if (a.buoyancy) fb += load(c, CornerLoad::buoy_y);
        if (a.drag) k += load(c, CornerLoad::drag_k);
      }
    }
  } else {
    for (int32_t j0 = a.start[i]; j0 < end; j0 += Batch) {
      const int nb = end - j0 < Batch ? end - j0 : Batch;
      size_t c[Batch];
      for (int u = 0; u < nb; ++u) c[u] = size_t(a.slot[j0 + u]);
      double lx[Batch], ly[Batch], lvx[Batch] = {}, lvy[Batch] = {}, lb[Batch] = {}, lk[Batch] = {};
      for (int u = 0; u < nb; ++u) {
        lx[u] = load(c[u], CornerLoad::fx);
        ly[u] = load(c[u], CornerLoad::fy);
        if (a.damping) {
          lvx[u] = load(c[u], CornerLoad::visc_x);
          lvy[u] = load(c[u], CornerLoad::visc_y);
        }
        if (a.water) {
          if (a.buoyancy) lb[u] = load(c[u], CornerLoad::buoy_y);
          if (a.drag) lk[u] = load(c[u], CornerLoad::drag_k);
        }
      }
      for (int u = 0; u < nb; ++u) {
        fx += lx[u];
        fy += ly[u];
        if (a.damping) {
          vx += lvx[u];
          vy += lvy[u];
        }
        if (a.water) {
          if (a.buoyancy) fb += lb[u];
          if (a.drag) k += lk[u];
        }
      }
    }
  }
  a.f_int_x[i] = fx;
  a.f_int_y[i] = fy;
  a.f_visc_x[i] = vx;
  a.f_visc_y[i] = vy;
  a.f_buoy_y[i] = fb;
  a.drag_k[i] = k;
  a.f_x[i] = fx - k * a.vx[i];
  // Weight from the physical mass: mass scaling adds inertia, not weight.
  a.f_y[i] = fy + fb - k * a.vy[i] - a.mass_phys[i] * a.g;
  a.f_coh_x[i] = a.f_coh_y[i] = 0.0;
}

}  // namespace engine
