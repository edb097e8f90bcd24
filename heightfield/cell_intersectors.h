// Ray / cell intersection: the ways of hitting one grid cell, from exact to naive.
//
// All methods work in cell-local coordinates: u = x - i and v = y - j in grid units, z in metres, and a
// segment parameter s = t - tEnter in [0, length]. G(s) = h(u(s), v(s)) - z(s) is the height of the surface
// above the ray; a hit is the smallest s with G(s) = 0, whichever way the ray crosses.
//
// Watertightness: G at the cell's entry and exit (gEntry, gExit) are computed once per shared boundary by
// the traversal, from the two vertices of that edge only, so neighbouring cells see bit-identical values.
// Whenever gEntry and gExit differ in sign a method must report a hit inside the cell, even if rounding
// pushed its own root just outside; a crossing therefore cannot slip between two cells.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>

namespace terracast {

// The cell intersectors are always inlined into the traversal's walk: out of line, the call and the registers
// it saves around it cost more than the common early rejection, and inlined, their divisions and square root
// overlap with the walk's own work.
#define TERRACAST_CELL_INLINE __attribute__((always_inline)) inline

// The four corner heights of a cell: h00 at (i, j), h10 at (i+1, j), h01 at (i, j+1), h11 at (i+1, j+1).
template <class Real>
struct CellCorners {
    Real h00, h10, h01, h11;

    // Bilinear coefficients: h(u, v) = a + b u + c v + d u v.
    Real a() const { return h00; }
    Real b() const { return h10 - h00; }
    Real c() const { return h01 - h00; }
    Real d() const { return (h00 - h10) - (h01 - h11); }
};

// A ray segment inside one cell, in cell-local coordinates.
template <class Real>
struct CellSegment {
    Real u0, v0, z0;     // entry point
    Real du, dv, dz;     // change per unit s
    Real length;         // s runs over [0, length]
    Real gEntry, gExit;  // surface height above the ray at s = 0 and s = length (shared with neighbours)
};

// a*b - c*d with one rounding error, by Kahan's FMA algorithm. In float the products are formed exactly in
// double instead (24-bit significands multiply into 48 bits), which needs no FMA instruction.
template <class Real>
inline Real differenceOfProducts(Real a, Real b, Real c, Real d) {
    if constexpr (std::is_same_v<Real, float>)
        return float(double(a) * double(b) - double(c) * double(d));
    const Real cd = c * d;
    const Real err = std::fma(-c, d, cd);
    const Real dop = std::fma(a, b, -cd);
    return dop + err;
}

// sqrt(B^2 - 4 A C), or a negative value when the discriminant is negative. In float the discriminant is formed
// and rooted in double: its exact products fit double's significand, and its magnitude, the square of the
// coefficients', leaves float's range for coefficients below about 1e-19 or above 1e19 (a nearly flat cell
// crossed by a nearly vertical ray). Rounded to zero there, it would turn two distinct roots into one.
template <class Real>
inline Real discriminantRoot(Real A, Real B, Real C) {
    if constexpr (std::is_same_v<Real, float>) {
        const double disc = differenceOfProducts(double(B), double(B), 4.0 * double(A), double(C));
        return disc >= 0.0 ? float(std::sqrt(disc)) : -1.0f;
    } else {
        const Real disc = differenceOfProducts(B, B, Real(4) * A, C);
        return disc >= Real(0) ? std::sqrt(disc) : Real(-1);
    }
}

// The crossing of a piece [sa, sb] on which G is linear (or on which a crossing is guaranteed because G
// changes sign), from the end values ga = G(sa) and gb = G(sb); none when G keeps one strict sign.
template <class Real>
inline std::optional<Real> signChangeCrossing(Real sa, Real sb, Real ga, Real gb) {
    if (ga == Real(0)) return sa;
    if ((ga < Real(0)) == (gb < Real(0)) && gb != Real(0)) return std::nullopt;
    const Real denom = ga - gb;
    const Real frac = denom != Real(0) ? ga / denom : Real(0);
    return std::clamp(sa + (sb - sa) * frac, sa, sb);
}

// The crossing that a sign change of G between the cell's entry and exit guarantees, used when a method's
// own root search found none inside the segment because of rounding.
template <class Real>
inline std::optional<Real> guaranteedCrossing(const CellSegment<Real>& seg) {
    return signChangeCrossing(Real(0), seg.length, seg.gEntry, seg.gExit);
}

// Exact ray / bilinear-patch intersection (Ramsey, Potter, Hansen 2004, "Ray Bilinear Patch
// Intersections", JGT 9(3)). Substituting the segment into h(u, v) gives A s^2 + B s + C = 0 with
//   A = d du dv,  B = b du + c dv + d (u0 dv + v0 du) - dz,  C = G(0).
// The roots use the cancellation-free form q = -(B + sign(B) sqrt(B^2 - 4AC)) / 2, s = q / A and C / q,
// with the discriminant from an FMA difference of products (in double for float: see discriminantRoot); A == 0
// (planar cell, or a ray parallel to an axis) is solved as the linear equation B s + C = 0. The ray's z never
// enters the elimination, so horizontal rays are ordinary.
template <class Real>
TERRACAST_CELL_INLINE std::optional<Real> intersectBilinearCell(const CellCorners<Real>& h,
                                                                const CellSegment<Real>& seg) {
    const Real b = h.b(), c = h.c(), d = h.d();
    const Real A = d * seg.du * seg.dv;
    const Real B = b * seg.du + c * seg.dv + d * (seg.u0 * seg.dv + seg.v0 * seg.du) - seg.dz;
    const Real C = seg.gEntry;
    if (C == Real(0)) return Real(0);
    // The ray above the surface at both ends (the usual near miss): G can only come back up to zero inside
    // when it is concave (A < 0) with its maximum inside the segment, where G' = 2 A s + B changes sign.
    if (C < Real(0) && seg.gExit < Real(0) && !(A < Real(0) && B > Real(0) && B + Real(2) * A * seg.length < Real(0)))
        return std::nullopt;

    Real r0 = std::numeric_limits<Real>::infinity(), r1 = r0;
    if (A == Real(0)) {
        if (B != Real(0)) r0 = -C / B;
    } else {
        const Real root = discriminantRoot(A, B, C);
        if (root >= Real(0)) {
            const Real q = Real(-0.5) * (B + std::copysign(root, B));
            r0 = q / A;
            r1 = q != Real(0) ? C / q : r0;
            if (r1 < r0) std::swap(r0, r1);
        }
    }
    if (Real(0) <= r0 && r0 <= seg.length) return r0;
    if (Real(0) <= r1 && r1 <= seg.length) return r1;
    return guaranteedCrossing(seg);
}

// Two triangles per cell split along the diagonal from (i+1, j) to (i, j+1), the diagonal of Embree's grid
// geometry: T0 = (00, 10, 01) where u + v <= 1 and T1 = (10, 11, 01) where u + v >= 1. G is linear on each
// triangle, so the segment is cut where it crosses the diagonal and each piece is solved from its end values.
template <class Real>
TERRACAST_CELL_INLINE std::optional<Real> intersectTrianglesCell(const CellCorners<Real>& h,
                                                                 const CellSegment<Real>& seg) {
    if (seg.gEntry == Real(0)) return Real(0);
    const Real w0 = seg.u0 + seg.v0 - Real(1);  // signed distance from the diagonal (scaled)
    const Real dw = seg.du + seg.dv;
    const Real sDiag = dw != Real(0) ? -w0 / dw : Real(-1);
    if (sDiag > Real(0) && sDiag < seg.length) {
        // The diagonal height is linear between h10 (v = 0) and h01 (v = 1), the same for both triangles.
        const Real v = std::clamp(seg.v0 + sDiag * seg.dv, Real(0), Real(1));
        const Real gDiag = ((Real(1) - v) * h.h10 + v * h.h01) - (seg.z0 + sDiag * seg.dz);
        if (auto s = signChangeCrossing(Real(0), sDiag, seg.gEntry, gDiag)) return s;
        return signChangeCrossing(sDiag, seg.length, gDiag, seg.gExit);
    }
    return guaranteedCrossing(seg);
}

// Which of the two triangles holds the local point (u, v).
template <class Real>
inline bool inUpperTriangle(Real u, Real v) {
    return u + v > Real(1);
}

// The naive flat cell: a square at the mean of the four corners, with vertical walls where neighbouring
// squares differ. A segment entering below the square hits the wall at its entry.
template <class Real>
TERRACAST_CELL_INLINE std::optional<Real> intersectNearestCell(const CellCorners<Real>& h,
                                                               const CellSegment<Real>& seg) {
    const Real level = Real(0.25) * ((h.h00 + h.h10) + (h.h01 + h.h11));
    const Real gEntry = level - seg.z0;
    if (gEntry >= Real(0)) return Real(0);
    const Real gExit = level - (seg.z0 + seg.length * seg.dz);
    if (gExit < Real(0)) return std::nullopt;
    if (seg.dz == Real(0)) return std::nullopt;
    return std::clamp((level - seg.z0) / seg.dz, Real(0), seg.length);
}

}  // namespace terracast
