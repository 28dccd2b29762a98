// Every stored field of the freeze bonds, listed once. The struct-of-arrays
// (BondInput, BondState), their initial values, sizes checks, memory_bytes,
// checkpoints and the Python dicts are all generated from these two lists, so
// a new field is one new line here and nowhere else.
//
// X(extent, type, name, initial value, doc)
//   extent: point (one per bond point), pair (one per cohesive pair),
//           split_node (one per node appended by splitting), total (a scalar).
// The names are the Python dict keys (bond_input(), bond_state()).
#pragma once
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "cohesive_law/softening.hpp"

namespace engine {

// Codes of BondState::point_state (Python: _engine.PointState).
enum class PointState : int8_t { intact = 0, split = 1 };
// Codes of BondState::pair_state (Python: _engine.PairState).
enum class PairState : int8_t { intact = 0, cohesive = 1, failed = 2 };
// Codes of BondState::mode (Python: _engine.FailureMode): the cohesive law's.
using FailureMode = cohesive_law::FailureMode;

enum class BondExtent { point, pair, split_node, total };

namespace bond_fields {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace bond_fields

// The static description of the bonds, as found from the mesh
// (icerubble/geometry/bond_points.py). Pairs are grouped by point (pair_point
// non-decreasing) and every point has at least one pair.
#define ENGINE_BOND_INPUT_FIELDS(X)                                                           \
  X(point, int32_t, node, 0, "mesh node id")                                                  \
  X(point, double, sigma_cr, 0.0, "tensile strength [Pa]")                                    \
  X(point, double, tau_cr, 0.0, "shear strength [Pa]")                                        \
  X(point, double, G, 0.0, "fracture energy [J/m²]")                                          \
  X(pair, int32_t, pair_point, 0, "bond point of the pair")                                   \
  X(pair, int32_t, body_minus, 0, "body the bond normal points from")                         \
  X(pair, int32_t, body_plus, 0, "body the bond normal points to")                            \
  X(pair, double, nx, 0.0, "bond normal in the reference configuration, x")                   \
  X(pair, double, ny, 0.0, "bond normal in the reference configuration, y")                   \
  X(pair, double, length, 0.0, "l [m]: half of the pair's bond edges at the node")            \
  /* Two nodes whose reference-to-current rotation turns the normal of an intact pair */      \
  /* (the ends of its bond edges at the node, or the node and its only edge's far end). */    \
  X(pair, int32_t, frame_p, 0, "first frame node")                                            \
  X(pair, int32_t, frame_q, 0, "second frame node")

// Everything that changes in a run: what a checkpoint must carry.
#define ENGINE_BOND_STATE_FIELDS(X)                                                           \
  X(point, PointState, point_state, PointState::intact, "PointState code")                    \
  /* everything is checked on the first step */                                              \
  X(point, int8_t, near, 1, "pre-screening flag: check at the next step")                     \
  X(point, double, t_split, bond_fields::kNaN, "time of the split [s]")                       \
  X(point, double, x_split, bond_fields::kNaN, "position of the split, x [m]")                \
  X(point, double, y_split, bond_fields::kNaN, "position of the split, y [m]")                \
  X(pair, PairState, pair_state, PairState::intact, "PairState code")                         \
  X(pair, int32_t, node_plus, -1, "node on the + side after the split")                       \
  X(pair, int32_t, node_minus, -1, "node on the - side after the split")                      \
  X(pair, double, fnx, 0.0, "bond normal frozen at the split, x")                             \
  X(pair, double, fny, 0.0, "bond normal frozen at the split, y")                             \
  X(pair, double, f0, 0.0, "initial cohesive force, eq 8 [N/m]")                              \
  X(pair, double, delta_f, 0.0, "opening at full failure, eq 12 [m]")                         \
  X(pair, double, delta_m, 0.0, "largest effective opening so far [m]")                       \
  X(pair, double, f_n_prev, 0.0, "normal cohesive force of the last step [N/m]")              \
  X(pair, double, f_t_prev, 0.0, "tangential cohesive force of the last step [N/m]")          \
  X(pair, double, d_n_prev, 0.0, "normal opening of the last step [m]")                       \
  X(pair, double, d_t_prev, 0.0, "tangential opening of the last step [m]")                   \
  X(pair, double, split_tn, bond_fields::kNaN, "normal traction at the split [Pa]")           \
  X(pair, double, split_tt, bond_fields::kNaN, "tangential traction at the split [Pa]")       \
  X(pair, double, t_fail, bond_fields::kNaN, "time of full failure [s]")                      \
  X(pair, double, x_fail, bond_fields::kNaN, "position of full failure, x [m]")               \
  X(pair, double, y_fail, bond_fields::kNaN, "position of full failure, y [m]")               \
  X(pair, double, dn_fail, bond_fields::kNaN, "normal opening at full failure [m]")           \
  X(pair, double, dt_fail, bond_fields::kNaN, "tangential opening at full failure [m]")       \
  X(pair, FailureMode, mode, FailureMode::none, "FailureMode code")                           \
  X(split_node, int32_t, parent, 0, "original node of each node appended by splitting")       \
  X(total, double, work, 0.0, "work done against the cohesive forces [J/m]")                  \
  X(total, double, dissipation_effective, 0.0, "sum 1/2 f0 delta_m [J/m]")                    \
  X(total, double, stored, 0.0, "energy stored on the secant branches [J/m]")                 \
  X(total, int64_t, late_detections, 0, "failures found up to screen_interval-1 steps late")  \
  X(total, int64_t, checks, 0, "point checks evaluated")

template <class T> struct IsBondArray : std::false_type {};
template <class T> struct IsBondArray<std::vector<T>> : std::true_type {};
// True for the array fields (per point, pair or split node), false for totals.
template <class Field>
constexpr bool is_bond_array = IsBondArray<std::decay_t<Field>>::value;

template <BondExtent E, class T>
using BondField = std::conditional_t<E == BondExtent::total, T, std::vector<T>>;

#define ENGINE_BOND_DECLARE(E, T, name, init, doc) BondField<BondExtent::E, T> name{};
#define ENGINE_BOND_VISIT(E, T, name, init, doc) f(#name, BondExtent::E, s.name, T(init));

struct BondInput {
  ENGINE_BOND_INPUT_FIELDS(ENGINE_BOND_DECLARE)
  // f(key, extent, field, initial value) for every field, in list order.
  template <class Self, class F>
  static void each(Self& s, F&& f) { ENGINE_BOND_INPUT_FIELDS(ENGINE_BOND_VISIT) }
};

struct BondState {
  ENGINE_BOND_STATE_FIELDS(ENGINE_BOND_DECLARE)
  template <class Self, class F>
  static void each(Self& s, F&& f) { ENGINE_BOND_STATE_FIELDS(ENGINE_BOND_VISIT) }
};

#undef ENGINE_BOND_DECLARE
#undef ENGINE_BOND_VISIT

}  // namespace engine
