#include "tracer/scene/primitives.h"

#include "tracer/core/angles.h"

#include "heightfield/shading_normals.h"

#include <cmath>
#include <limits>

namespace terracast {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// A rounding-error bound for a point computed in double from coordinates of this magnitude: a generous
// multiple of the unit roundoff, so a spawned ray never starts on the wrong side of the surface it leaves.
double pointError(const glm::dvec3& p, double extra = 0.0) {
    const double m = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), extra, 1.0});
    return 64.0 * kEps * m;
}

double maxAbs(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

}  // namespace

bool Bounds3::finite() const {
    return std::isfinite(lo.x) && std::isfinite(lo.y) && std::isfinite(lo.z) && std::isfinite(hi.x) &&
           std::isfinite(hi.y) && std::isfinite(hi.z) && lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z;
}

Interval Bounds3::clip(const Ray& ray, Interval interval) const {
    for (int a = 0; a < 3; ++a) {
        const double inv = 1.0 / ray.dir[a];
        double t0 = (lo[a] - ray.origin[a]) * inv, t1 = (hi[a] - ray.origin[a]) * inv;
        if (t0 > t1) std::swap(t0, t1);
        if (std::isnan(t0) || std::isnan(t1)) {
            // The ray runs parallel to the slab with its origin on a face: inside when within the slab.
            if (ray.origin[a] < lo[a] || ray.origin[a] > hi[a]) return {1.0, 0.0};
            continue;
        }
        // Widen by a few ulps so that rays grazing a face are not lost (Ize 2013, "Robust BVH ray traversal").
        t1 *= 1.0 + 4.0 * kEps;
        interval.lo = std::max(interval.lo, t0);
        interval.hi = std::min(interval.hi, t1);
        if (interval.empty()) return interval;
    }
    return interval;
}

glm::dvec3 offsetOrigin(const SurfaceHit& hit, const glm::dvec3& dir) {
    const double side = glm::dot(hit.normal, dir) >= 0.0 ? 1.0 : -1.0;
    return hit.point + side * hit.errorM * hit.normal;
}

// Sphere: solving |o + t d - c|^2 = r^2 with the discriminant written as r^2 - |f - (f.d) d|^2, which keeps
// its precision for distant spheres (Haines et al., "Precision improvements for ray/sphere intersection",
// Ray Tracing Gems, 2019). Directions are unit length.
bool SpherePrimitive::intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const {
    const glm::dvec3 d = ray.dir;
    const double a = glm::dot(d, d);
    const glm::dvec3 f = ray.origin - centre_;
    const double b = -glm::dot(f, d);  // = a * t of the closest approach
    const glm::dvec3 l = f + (b / a) * d;
    const double disc = a * (radius_ * radius_ - glm::dot(l, l));
    if (disc < 0.0) return false;
    const double q = b + std::copysign(std::sqrt(disc), b);
    // The product of the roots is c / a with c = |f|^2 - r^2: the second root comes from the first without
    // cancellation.
    double t0 = q / a;
    double t1 = q != 0.0 ? (glm::dot(f, f) - radius_ * radius_) / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    double t = t0;
    if (!interval.contains(t)) {
        t = t1;
        if (!interval.contains(t)) return false;
    }
    hit.t = t;
    hit.point = ray.at(t);
    hit.normal = glm::normalize(hit.point - centre_);
    hit.point = centre_ + radius_ * hit.normal;  // reprojected onto the sphere
    hit.errorM = pointError(hit.point, radius_);
    // u: longitude from +x (0.5 there), counter-clockwise; v: 0 at the south pole, 1 at the north pole.
    hit.uv = {0.5 + std::atan2(hit.normal.y, hit.normal.x) / (2.0 * kPi),
              1.0 - std::acos(std::clamp(hit.normal.z, -1.0, 1.0)) / kPi};
    return true;
}

Bounds3 SpherePrimitive::bounds() const { return {centre_ - glm::dvec3(radius_), centre_ + glm::dvec3(radius_)}; }

PlanePrimitive::PlanePrimitive(const glm::dvec3& point, const glm::dvec3& normal)
    : point_(point), normal_(glm::normalize(normal)) {
    // u runs level across the plane (east on a level plane), v up its slope (north on a level plane).
    const glm::dvec3 across = glm::cross(glm::dvec3(0.0, 0.0, 1.0), normal_);
    uAxis_ = glm::dot(across, across) > 1e-12 ? glm::normalize(across) : glm::dvec3(1.0, 0.0, 0.0);
    if (glm::dot(across, across) <= 1e-12 && normal_.z < 0.0) uAxis_ = {-1.0, 0.0, 0.0};
    vAxis_ = glm::cross(normal_, uAxis_);
}

bool PlanePrimitive::intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const {
    const double denom = glm::dot(ray.dir, normal_);
    if (denom == 0.0) return false;
    const double t = glm::dot(point_ - ray.origin, normal_) / denom;
    if (!interval.contains(t)) return false;
    hit.t = t;
    hit.point = ray.at(t);
    hit.normal = normal_;
    hit.errorM = pointError(hit.point, maxAbs(point_));
    hit.uv = {glm::dot(hit.point, uAxis_), glm::dot(hit.point, vAxis_)};
    return true;
}

Bounds3 PlanePrimitive::bounds() const { return {glm::dvec3(-kInfinity), glm::dvec3(kInfinity)}; }

TrianglePrimitive::TrianglePrimitive(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
    : a_(a), e1_(b - a), e2_(c - a), normal_(glm::normalize(glm::cross(b - a, c - a))) {}

// Moller and Trumbore 1997, "Fast, minimum storage ray-triangle intersection", in double precision.
bool TrianglePrimitive::intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const {
    const glm::dvec3 p = glm::cross(ray.dir, e2_);
    const double det = glm::dot(e1_, p);
    if (det == 0.0) return false;
    const double inv = 1.0 / det;
    const glm::dvec3 s = ray.origin - a_;
    const double u = glm::dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) return false;
    const glm::dvec3 q = glm::cross(s, e1_);
    const double v = glm::dot(ray.dir, q) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    const double t = glm::dot(e2_, q) * inv;
    if (!interval.contains(t)) return false;
    hit.t = t;
    hit.point = a_ + u * e1_ + v * e2_;
    hit.normal = normal_;
    hit.uv = {u, v};
    hit.errorM = pointError(hit.point, maxAbs(a_) + maxAbs(e1_) + maxAbs(e2_));
    return true;
}

Bounds3 TrianglePrimitive::bounds() const {
    Bounds3 b;
    b.extend(a_);
    b.extend(a_ + e1_);
    b.extend(a_ + e2_);
    return b;
}

glm::dvec3 PolygonPrimitive::newellNormal(const std::vector<glm::dvec3>& v) {
    glm::dvec3 n{0.0};
    const size_t count = v.size();
    for (size_t k = 0; k < count; ++k) {
        const glm::dvec3& p = v[k];
        const glm::dvec3& q = v[(k + 1) % count];
        n += glm::dvec3((p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x), (p.x - q.x) * (p.y + q.y));
    }
    const double len = glm::length(n);
    return len > 0.0 ? n / len : glm::dvec3(0.0);
}

PolygonPrimitive::PolygonPrimitive(std::vector<glm::dvec3> vertices)
    : vertices_(std::move(vertices)), normal_(newellNormal(vertices_)) {
    const glm::dvec3 a = glm::abs(normal_);
    dropAxis_ = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    for (const auto& p : vertices_) bounds_.extend(p);
}

// The even-odd (crossing number) test in 2D: count the polygon edges a ray from p along +u crosses.
bool PolygonPrimitive::contains(const glm::dvec3& p) const {
    const int ua = dropAxis_ == 0 ? 1 : 0;
    const int va = dropAxis_ == 2 ? 1 : 2;
    const double pu = p[ua], pv = p[va];
    bool inside = false;
    const size_t count = vertices_.size();
    for (size_t k = 0, prev = count - 1; k < count; prev = k++) {
        const double u0 = vertices_[prev][ua], v0 = vertices_[prev][va];
        const double u1 = vertices_[k][ua], v1 = vertices_[k][va];
        // Half-open rule on v, so a vertex exactly at pv is counted once.
        if ((v0 > pv) != (v1 > pv)) {
            const double uCross = u0 + (pv - v0) * (u1 - u0) / (v1 - v0);
            if (pu < uCross) inside = !inside;
        }
    }
    return inside;
}

bool PolygonPrimitive::intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const {
    const double denom = glm::dot(ray.dir, normal_);
    if (denom == 0.0) return false;
    const double t = glm::dot(vertices_[0] - ray.origin, normal_) / denom;
    if (!interval.contains(t)) return false;
    const glm::dvec3 p = ray.at(t);
    if (!contains(p)) return false;
    hit.t = t;
    hit.point = p;
    hit.normal = normal_;
    hit.uv = {p[dropAxis_ == 0 ? 1 : 0], p[dropAxis_ == 2 ? 1 : 2]};
    hit.errorM = pointError(p, std::max(maxAbs(bounds_.lo), maxAbs(bounds_.hi)));
    return true;
}

Bounds3 PolygonPrimitive::bounds() const { return bounds_; }

// Slabs (Kay and Kajiya 1986): the entry face gives the normal; a ray starting inside hits the exit face.
bool BoxPrimitive::intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const {
    double tNear = -kInfinity, tFar = kInfinity;
    int nearAxis = -1, farAxis = -1;
    double nearSign = 0.0, farSign = 0.0;
    for (int a = 0; a < 3; ++a) {
        if (ray.dir[a] == 0.0) {
            if (ray.origin[a] < box_.lo[a] || ray.origin[a] > box_.hi[a]) return false;
            continue;
        }
        const double inv = 1.0 / ray.dir[a];
        double t0 = (box_.lo[a] - ray.origin[a]) * inv, t1 = (box_.hi[a] - ray.origin[a]) * inv;
        double s0 = -1.0, s1 = 1.0;  // outward normal sign of the face met at t0 and t1
        if (t0 > t1) {
            std::swap(t0, t1);
            std::swap(s0, s1);
        }
        if (t0 > tNear) {
            tNear = t0;
            nearAxis = a;
            nearSign = s0;
        }
        if (t1 < tFar) {
            tFar = t1;
            farAxis = a;
            farSign = s1;
        }
    }
    if (tNear > tFar) return false;
    double t = tNear;
    int axis = nearAxis;
    double sign = nearSign;
    if (!interval.contains(t) || axis < 0) {
        t = tFar;
        axis = farAxis;
        sign = farSign;
        if (!interval.contains(t) || axis < 0) return false;
    }
    hit.t = t;
    hit.point = ray.at(t);
    hit.point[axis] = sign < 0.0 ? box_.lo[axis] : box_.hi[axis];  // exactly on the face
    hit.normal = glm::dvec3(0.0);
    hit.normal[axis] = sign;
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    hit.uv = {hit.point[ua], hit.point[va]};
    hit.errorM = pointError(hit.point, std::max(maxAbs(box_.lo), maxAbs(box_.hi)));
    return true;
}

HeightFieldPrimitive::HeightFieldPrimitive(std::shared_ptr<const HeightGrid> grid, const glm::dvec3& offsetM,
                                           SurfaceMethod method, int threads, bool smoothNormals)
    : grid_(std::move(grid)), offset_(offsetM), surface_(*grid_, method, threads), smoothNormals_(smoothNormals) {}

bool HeightFieldPrimitive::intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const {
    const Ray local{ray.origin - offset_, ray.dir, ray.time};
    const auto h = surface_.intersect(local, interval);
    if (!h) return false;
    hit.t = h->t;
    hit.point = h->pointM + offset_;
    hit.normal = h->normal;
    hit.uv = {(double(h->cellX) + h->u) / double(grid_->cellsX()), (double(h->cellY) + h->v) / double(grid_->cellsY())};
    hit.errorM = std::max(h->errorM, pointError(hit.point));
    if (smoothNormals_) hit.shading = smoothNormal(*grid_, h->cellX, h->cellY, h->u, h->v);
    return true;
}

bool HeightFieldPrimitive::occluded(const Ray& ray, Interval interval) const {
    return surface_.occluded({ray.origin - offset_, ray.dir, ray.time}, interval);
}

Bounds3 HeightFieldPrimitive::bounds() const {
    return {offset_ + glm::dvec3(0.0, 0.0, grid_->minHeightM()),
            offset_ + glm::dvec3(grid_->extentXM(), grid_->extentYM(), grid_->maxHeightM())};
}

WaterPrimitive::WaterPrimitive(double levelM, const HeightFieldPrimitive& terrain) : level_(levelM) {
    const HeightGrid& g = terrain.grid();
    const glm::dvec3 o = terrain.offset();
    x0_ = o.x;
    y0_ = o.y;
    x1_ = o.x + g.extentXM();
    y1_ = o.y + g.extentYM();
    stepX_ = g.cellSizeXM();
    stepY_ = g.cellSizeYM();
    lowest_ = levelM;
    const auto height = [&](int64_t i, int64_t j) {
        return g.vertexValid(i, j) ? o.z + double(g.at(i, j)) : kInfinity;
    };
    for (int64_t j = 0; j < g.height(); ++j) {
        edges_[0].push_back(height(0, j));
        edges_[1].push_back(height(g.width() - 1, j));
    }
    for (int64_t i = 0; i < g.width(); ++i) {
        edges_[2].push_back(height(i, 0));
        edges_[3].push_back(height(i, g.height() - 1));
    }
    for (const auto& edge : edges_)
        for (const double z : edge) lowest_ = std::min(lowest_, z);
}

double WaterPrimitive::edgeHeight(int side, double along) const {
    const std::vector<double>& edge = edges_[side];
    const double s = side < 2 ? (along - y0_) / stepY_ : (along - x0_) / stepX_;
    const double k = std::clamp(std::floor(s), 0.0, double(edge.size() - 2));
    const double f = std::clamp(s - k, 0.0, 1.0);
    const double a = edge[size_t(k)], b = edge[size_t(k) + 1];
    if (!std::isfinite(a) || !std::isfinite(b)) return kInfinity;
    return a + (b - a) * f;
}

bool WaterPrimitive::intersect(const Ray& ray, Interval interval, SurfaceHit& hit) const {
    double best = kInfinity;
    glm::dvec3 normal{0.0};
    glm::dvec3 point{0.0};
    // The surface.
    if (ray.dir.z != 0.0) {
        const double t = (level_ - ray.origin.z) / ray.dir.z;
        const glm::dvec3 p = ray.at(t);
        if (interval.contains(t) && covers(p.x, p.y)) {
            best = t;
            normal = {0.0, 0.0, 1.0};
            point = {p.x, p.y, level_};
        }
    }
    // The sides, between the terrain's edge and the level.
    for (int side = 0; side < 4; ++side) {
        const int axis = side < 2 ? 0 : 1;
        if (ray.dir[axis] == 0.0) continue;
        const double plane = side == 0 ? x0_ : side == 1 ? x1_ : side == 2 ? y0_ : y1_;
        const double t = (plane - ray.origin[axis]) / ray.dir[axis];
        if (!(t < best) || !interval.contains(t)) continue;
        glm::dvec3 p = ray.at(t);
        p[axis] = plane;
        const double along = axis == 0 ? p.y : p.x;
        const bool within = axis == 0 ? along >= y0_ && along <= y1_ : along >= x0_ && along <= x1_;
        if (!within || p.z > level_ || p.z < edgeHeight(side, along)) continue;
        best = t;
        normal = glm::dvec3(0.0);
        normal[axis] = side % 2 == 0 ? -1.0 : 1.0;
        point = p;
    }
    if (!std::isfinite(best)) return false;
    hit.t = best;
    hit.point = point;
    hit.normal = normal;
    hit.uv = {(point.x - x0_) / (x1_ - x0_), (point.y - y0_) / (y1_ - y0_)};
    hit.errorM = pointError(point, std::max({std::abs(x0_), std::abs(x1_), std::abs(y0_), std::abs(y1_)}));
    return true;
}

Bounds3 WaterPrimitive::bounds() const {
    const double pad = pointError({x1_, y1_, level_}, std::max(std::abs(x0_), std::abs(y0_)));
    return {{x0_ - pad, y0_ - pad, std::min(lowest_, level_) - pad}, {x1_ + pad, y1_ + pad, level_ + pad}};
}

}  // namespace terracast
