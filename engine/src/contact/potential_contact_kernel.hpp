// The potential contact pair kernel (potential_contact.hpp explains the
// formulas and the energy they derive from), written once for both backends:
// the CPU's ContactSolver calls it per candidate pair, the GPU backend per
// candidate per lane (cuda/contact_normal.cu).
#pragma once
#include <cmath>

#include "common/host_device.hpp"
#include "contact/potential_contact.hpp"

namespace engine {
namespace contact_kernel {

// A triangle cut by 3 half-planes has at most 6 vertices, by 2 more at most 8.
constexpr int kMaxPoly = 12;

// No initializer: a polygon is made by clip (or from a triangle's corners)
// before it is read, and the GPU keeps an Overlap's in shared memory, which
// takes no initialization (cuda/contact_normal.cu).
struct Poly {
  int n;
  double x[kMaxPoly];
  double y[kMaxPoly];
};

// A counter-clockwise triangle in the local frame with its area-coordinate
// gradients: lambda_k(p) = 1/3 + gx[k] (px - cx) + gy[k] (py - cy).
struct Tri {
  double x[3], y[3];
  double cx, cy;
  double gx[3], gy[3];
  int perm[3];  // local vertex k is caller's vertex perm[k]

  ICERUBBLE_HD double lambda(int k, double px, double py) const {
    return 1.0 / 3.0 + gx[k] * (px - cx) + gy[k] * (py - cy);
  }
};

// Sets up `t` from the caller's vertices shifted by (ox, oy); makes it
// counter-clockwise. Returns false for a degenerate triangle.
ICERUBBLE_HD bool make_tri(const double xs[3], const double ys[3], double ox, double oy, Tri& t) {
  double x[3], y[3];
  for (int k = 0; k < 3; ++k) {
    x[k] = xs[k] - ox;
    y[k] = ys[k] - oy;
  }
  const double a2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  if (!(fabs(a2) > 0.0)) return false;
  t.perm[0] = 0;
  t.perm[1] = a2 > 0 ? 1 : 2;
  t.perm[2] = a2 > 0 ? 2 : 1;
  for (int k = 0; k < 3; ++k) {
    t.x[k] = x[t.perm[k]];
    t.y[k] = y[t.perm[k]];
  }
  const double inv2a = 1.0 / fabs(a2);
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    t.gx[k] = (t.y[i] - t.y[j]) * inv2a;
    t.gy[k] = (t.x[j] - t.x[i]) * inv2a;
  }
  t.cx = (t.x[0] + t.x[1] + t.x[2]) / 3.0;
  t.cy = (t.y[0] + t.y[1] + t.y[2]) / 3.0;
  return true;
}

// Sutherland-Hodgman: keeps the part of `in` on the left of the directed line
// a -> b (the inside of a counter-clockwise polygon).
ICERUBBLE_HD void clip(const Poly& in, double ax, double ay, double bx, double by, Poly& out) {
  out.n = 0;
  if (in.n == 0) return;
  const double ex = bx - ax, ey = by - ay;
  double dprev = ex * (in.y[in.n - 1] - ay) - ey * (in.x[in.n - 1] - ax);
  double xprev = in.x[in.n - 1], yprev = in.y[in.n - 1];
  for (int i = 0; i < in.n; ++i) {
    const double xi = in.x[i], yi = in.y[i];
    const double d = ex * (yi - ay) - ey * (xi - ax);
    if ((d >= 0.0) != (dprev >= 0.0)) {
      const double s = dprev / (dprev - d);
      out.x[out.n] = xprev + s * (xi - xprev);
      out.y[out.n] = yprev + s * (yi - yprev);
      ++out.n;
    }
    if (d >= 0.0) {
      out.x[out.n] = xi;
      out.y[out.n] = yi;
      ++out.n;
    }
    dprev = d;
    xprev = xi;
    yprev = yi;
  }
}

// Area and centroid of a simple counter-clockwise polygon. Coordinates are
// taken relative to the first vertex: overlaps are thin slivers (penetrations
// of ~1e-10 m against edges of ~0.1 m) and this keeps their area accurate.
ICERUBBLE_HD double area_centroid(const Poly& p, double& gx, double& gy) {
  if (p.n < 3) return 0.0;
  const double x0 = p.x[0], y0 = p.y[0];
  double a2 = 0.0, sx = 0.0, sy = 0.0;
  for (int i = 1; i + 1 < p.n; ++i) {
    const double x1 = p.x[i] - x0, y1 = p.y[i] - y0;
    const double x2 = p.x[i + 1] - x0, y2 = p.y[i + 1] - y0;
    const double c = x1 * y2 - x2 * y1;
    a2 += c;
    sx += c * (x1 + x2);
    sy += c * (y1 + y2);
  }
  if (!(a2 > 0.0)) return 0.0;
  gx = x0 + sx / (3.0 * a2);
  gy = y0 + sy / (3.0 * a2);
  return 0.5 * a2;
}

// A pair's first part: both triangles in a frame at the target's centroid
// (ox, oy: overlaps are tiny compared with the global coordinates, so work
// with small numbers), the contactor clipped by the three target edges
// (ov), its area and centroid (local). False where a triangle is
// degenerate or the overlap has no positive area.
struct Overlap {
  Tri c, t;
  Poly ov;
  double ox, oy, area, gx, gy;
};

ICERUBBLE_HD bool overlap_of(const double xc[3], const double yc[3], const double xt[3], const double yt[3],
                             Overlap& o) {
  o.ox = (xt[0] + xt[1] + xt[2]) / 3.0;
  o.oy = (yt[0] + yt[1] + yt[2]) / 3.0;
  if (!make_tri(xc, yc, o.ox, o.oy, o.c) || !make_tri(xt, yt, o.ox, o.oy, o.t)) return false;
  Poly p0, p1;
  p0.n = 3;
  for (int k = 0; k < 3; ++k) {
    p0.x[k] = o.c.x[k];
    p0.y[k] = o.c.y[k];
  }
  clip(p0, o.t.x[0], o.t.y[0], o.t.x[1], o.t.y[1], p1);
  clip(p1, o.t.x[1], o.t.y[1], o.t.x[2], o.t.y[2], p0);
  clip(p0, o.t.x[2], o.t.y[2], o.t.x[0], o.t.y[0], o.ov);
  o.gx = o.gy = 0.0;
  o.area = area_centroid(o.ov, o.gx, o.gy);
  return o.area > 0.0;
}

// The force of the potential of an `owner` triangle acting on the overlap
// (which lies inside it), from one of its three sub-triangles i (node i1,
// node i2, centroid, where phi = 3 lambda_i): owner nodes get
// s A N^o_k(g) grad phi_o, the other triangle's nodes get
// -s A (N^p_j(g) grad phi_o + phi_o(g) grad N^p_j), and the energy is s A phi_o(g)
// (present: the overlap reaches into the sub-triangle). A pair has six: the
// target as owner (the contactor in the target's phi), sub-triangles 0-2,
// then the contactor as owner, 0-2 (pair_sub_term's j); each is computed
// alone, so the GPU computes a pair's six on six lanes (cuda/contact_normal.cu),
// and finish_pair adds them in that order on both backends: the same bits.
struct SubTerm {
  bool present;
  double energy;
  double fo_x[3], fo_y[3];  // added to the owner's nodes
  double fp_x[3], fp_y[3];  // taken from the other triangle's nodes
};

ICERUBBLE_HD void sub_term(const Tri& owner, const Tri& other, const Poly& ov, double s, int i, SubTerm& r) {
  const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
  Poly q, tmp;
  clip(ov, owner.x[i2], owner.y[i2], owner.cx, owner.cy, tmp);
  clip(tmp, owner.cx, owner.cy, owner.x[i1], owner.y[i1], q);
  double gx = 0.0, gy = 0.0;
  const double a = area_centroid(q, gx, gy);
  r.present = !(a <= 0.0);
  if (!r.present) return;
  const double sa = s * a;
  const double dphix = 3.0 * owner.gx[i], dphiy = 3.0 * owner.gy[i];
  const double phi = 3.0 * owner.lambda(i, gx, gy);
  r.energy = sa * phi;
  for (int k = 0; k < 3; ++k) {
    const double no = owner.lambda(k, gx, gy);
    r.fo_x[k] = sa * no * dphix;
    r.fo_y[k] = sa * no * dphiy;
    const double np = other.lambda(k, gx, gy);
    r.fp_x[k] = sa * (np * dphix + phi * other.gx[k]);
    r.fp_y[k] = sa * (np * dphiy + phi * other.gy[k]);
  }
}

// The pair's sub-term j (0-5, the order above).
ICERUBBLE_HD void pair_sub_term(const Overlap& o, double s, int j, SubTerm& r) {
  if (j < 3)
    sub_term(o.t, o.c, o.ov, s, j, r);
  else
    sub_term(o.c, o.t, o.ov, s, j - 3, r);
}

// Adds a sub-term to the owner's (fo) and the other's (fp) forces and the energy.
ICERUBBLE_HD void add_sub_term(const SubTerm& r, double& energy, double fo_x[3], double fo_y[3], double fp_x[3],
                               double fp_y[3]) {
  if (!r.present) return;
  energy += r.energy;
  for (int k = 0; k < 3; ++k) {
    fo_x[k] += r.fo_x[k];
    fo_y[k] += r.fo_y[k];
    fp_x[k] -= r.fp_x[k];
    fp_y[k] -= r.fp_y[k];
  }
}

// The pair's contact from its overlap and its six sub-terms (term(j): the
// sub-term j, SubTerm), added in their order (each owner's energy on its
// own, then the two added), in the caller's node order. The CPU computes
// each term as it is added (potential_contact_pair; six computed first made
// its contact forces ~20 % slower), the GPU's lanes computed them before
// (cuda/contact_normal.cu).
template <class Term>
ICERUBBLE_HD void finish_pair(const Overlap& o, Term term, PairContact& out) {
  double fcx[3] = {0, 0, 0}, fcy[3] = {0, 0, 0}, ftx[3] = {0, 0, 0}, fty[3] = {0, 0, 0};
  double energy = 0.0;
  for (int j = 0; j < 3; ++j) add_sub_term(term(j), energy, ftx, fty, fcx, fcy);  // contactor in target's phi
  double e_target = 0.0;
  for (int j = 3; j < 6; ++j) add_sub_term(term(j), e_target, fcx, fcy, ftx, fty);  // target in contactor's phi
  energy += e_target;
  for (int k = 0; k < 3; ++k) {
    out.fx[o.c.perm[k]] = fcx[k];
    out.fy[o.c.perm[k]] = fcy[k];
    out.fx[3 + o.t.perm[k]] = ftx[k];
    out.fy[3 + o.t.perm[k]] = fty[k];
    out.nc[o.c.perm[k]] = o.c.lambda(k, o.gx, o.gy);
    out.nt[o.t.perm[k]] = o.t.lambda(k, o.gx, o.gy);
  }
  out.energy = energy;
  out.area = o.area;
  out.px = o.gx + o.ox;
  out.py = o.gy + o.oy;
}

}  // namespace contact_kernel

ICERUBBLE_HD bool potential_contact_pair(const double xc[3], const double yc[3], const double xt[3],
                            const double yt[3], double s, PairContact& out) {
  using namespace contact_kernel;
  Overlap o;
  if (!overlap_of(xc, yc, xt, yt, o)) return false;
  finish_pair(o,
              [&](int j) {
                SubTerm r;
                pair_sub_term(o, s, j, r);
                return r;
              },
              out);
  return true;
}

// The largest and smallest of three corner coordinates. Plain comparisons,
// not fmax/fmin: the C library's are calls (their NaN rule keeps the
// compiler from inlining them): 4.5 % of the samples of a profile of the
// deep scene's load-phase steps when each candidate's box test made 16. The positions are finite (the broad
// phase and the stability guard stop a run otherwise), where both agree.
ICERUBBLE_HD double max3(const double v[3]) {
  const double m = v[0] > v[1] ? v[0] : v[1];
  return m > v[2] ? m : v[2];
}
ICERUBBLE_HD double min3(const double v[3]) {
  const double m = v[0] < v[1] ? v[0] : v[1];
  return m < v[2] ? m : v[2];
}

// A candidate pair (contactor a, target b: their corner coordinates): false
// when their current boxes are apart (candidates carry a skin) or they do not
// overlap with positive area; else their pair contact in `out`.
ICERUBBLE_HD bool boxes_apart(const double xa[3], const double ya[3], const double xb[3], const double yb[3]) {
  return max3(xa) < min3(xb) || max3(xb) < min3(xa) || max3(ya) < min3(yb) || max3(yb) < min3(ya);
}
ICERUBBLE_HD bool contact_candidate(const double xa[3], const double ya[3], const double xb[3],
                                    const double yb[3], double s, PairContact& out) {
  if (boxes_apart(xa, ya, xb, yb)) return false;
  return potential_contact_pair(xa, ya, xb, yb, s, out);
}

// The resultant of a touching pair's normal force on the contactor: its
// magnitude |f_c| and unit direction (friction's input, eq 4; 0 and (0, 0)
// where the forces cancel). A square root of the sum, not hypot: the C
// library's and CUDA's hypot differ in the last bits (docs/gpu.md).
ICERUBBLE_HD void contact_resultant(const PairContact& r, double& fn, double& nx, double& ny) {
  double rx = 0.0, ry = 0.0;
  for (int k = 0; k < 3; ++k) {
    rx += r.fx[k];
    ry += r.fy[k];
  }
  fn = sqrt(rx * rx + ry * ry);
  nx = fn > 0.0 ? rx / fn : 0.0;
  ny = fn > 0.0 ? ry / fn : 0.0;
}

}  // namespace engine
