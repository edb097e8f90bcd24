#include "tracer/sky/atmosphere.h"

#include "tracer/core/ranks.h"

#include "tracer/core/angles.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace terracast {

namespace {


double clampCosine(double mu) { return std::clamp(mu, -1.0, 1.0); }

// Distance from radius r along mu to the ground sphere (only meaningful when rayHitsGround).
double distanceToGround(const AtmosphereParameters& a, double r, double mu) {
    const double disc = r * r * (mu * mu - 1.0) + a.earthRadiusM * a.earthRadiusM;
    return std::max(0.0, -r * mu - std::sqrt(std::max(0.0, disc)));
}

// Radius at distance t from a point at radius r along mu (law of cosines).
double radiusAlong(double r, double mu, double t) { return std::sqrt(std::max(0.0, t * t + 2.0 * r * mu * t + r * r)); }

glm::dvec3 expNeg(const glm::dvec3& tau) { return {std::exp(-tau.x), std::exp(-tau.y), std::exp(-tau.z)}; }

double smoothstep(double lo, double hi, double x) {
    const double t = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

}  // namespace

glm::dvec3 AtmosphereParameters::extinctionAt(double altitudeM) const {
    const double h = std::max(0.0, altitudeM);
    return rayleighScattering * std::exp(-h / rayleighScaleHeightM) +
           glm::dvec3(haze * mieExtinction * std::exp(-h / mieScaleHeightM));
}

double rayleighPhase(double nu) { return 3.0 / (16.0 * kPi) * (1.0 + nu * nu); }

double henyeyGreensteinPhase(double nu, double g) {
    const double denom = 1.0 + g * g - 2.0 * g * nu;
    return (1.0 - g * g) / (4.0 * kPi * denom * std::sqrt(denom));
}

double distanceToTop(const AtmosphereParameters& a, double r, double mu) {
    const double disc = r * r * (mu * mu - 1.0) + a.topRadiusM * a.topRadiusM;
    return std::max(0.0, -r * mu + std::sqrt(std::max(0.0, disc)));
}

bool rayHitsGround(const AtmosphereParameters& a, double r, double mu) {
    return mu < 0.0 && r * r * (mu * mu - 1.0) + a.earthRadiusM * a.earthRadiusM >= 0.0;
}

glm::dvec3 opticalDepthToTop(const AtmosphereParameters& a, double r, double mu, int steps) {
    steps = std::max(2, steps + (steps & 1));  // Simpson's rule needs an even count
    const double d = distanceToTop(a, r, mu);
    const double dt = d / steps;
    glm::dvec3 sum(0.0);
    for (int i = 0; i <= steps; ++i) {
        const double w = (i == 0 || i == steps) ? 1.0 : (i & 1) ? 4.0 : 2.0;
        sum += w * a.extinctionAt(radiusAlong(r, mu, i * dt) - a.earthRadiusM);
    }
    return sum * (dt / 3.0);
}

// ---- Transmittance table -------------------------------------------------------------------------------------
// Bruneton's mapping: x_r = rho / H with rho = sqrt(r^2 - R^2) and H = sqrt(Rt^2 - R^2); x_mu places the
// distance to the top between its smallest (Rt - r, straight up) and largest (rho + H, along the horizon). Columns
// are packed towards the horizon (x_mu = 1 - (1 - u)^2), where optical depth changes fastest.

TransmittanceTable::TransmittanceTable(const AtmosphereParameters& a) : a_(a), depth_(size_t(kMuSize) * kRSize) {
    const double R = a.earthRadiusM, Rt = a.topRadiusM;
    const double H = std::sqrt(Rt * Rt - R * R);
    // Under ranks sharing their work, rank r fills the rows j with j mod K = r; the sum over the ranks completes
    // the table on every rank (as SkyTables does).
    const ranks::WorkShare share = ranks::workShare();
    tbb::parallel_for(0, kRSize, [&](int j) {
        if (!share.mine(j)) return;
        const double rho = H * double(j) / (kRSize - 1);
        const double r = std::sqrt(rho * rho + R * R);
        const double dMin = Rt - r, dMax = rho + H;
        for (int i = 0; i < kMuSize; ++i) {
            const double u = double(i) / (kMuSize - 1);
            const double d = dMin + (dMax - dMin) * (1.0 - (1.0 - u) * (1.0 - u));
            const double mu = d == 0.0 ? 1.0 : clampCosine((H * H - rho * rho - d * d) / (2.0 * r * d));
            depth_[size_t(j) * kMuSize + size_t(i)] = glm::vec3(opticalDepthToTop(a, r, mu, 32));
        }
    });
    if (share.shared) ranks::sumFloats(&depth_[0].x, depth_.size() * 3);  // optical depths: zero or positive
}

glm::dvec3 TransmittanceTable::opticalDepth(double r, double mu) const {
    const double R = a_.earthRadiusM, Rt = a_.topRadiusM;
    const double H = std::sqrt(Rt * Rt - R * R);
    r = std::clamp(r, R, Rt);
    const double rho = std::sqrt(std::max(0.0, r * r - R * R));
    const double d = distanceToTop(a_, r, mu);
    const double dMin = Rt - r, dMax = rho + H;
    const double xMu = dMax > dMin ? std::clamp((d - dMin) / (dMax - dMin), 0.0, 1.0) : 0.0;
    const double fx = (1.0 - std::sqrt(1.0 - xMu)) * (kMuSize - 1), fy = std::clamp(rho / H, 0.0, 1.0) * (kRSize - 1);
    const int i = std::min(int(fx), kMuSize - 2), j = std::min(int(fy), kRSize - 2);
    const double u = fx - i, v = fy - j;
    auto at = [&](int ii, int jj) { return glm::dvec3(depth_[size_t(jj) * kMuSize + size_t(ii)]); };
    return (1.0 - v) * ((1.0 - u) * at(i, j) + u * at(i + 1, j)) + v * ((1.0 - u) * at(i, j + 1) + u * at(i + 1, j + 1));
}

glm::dvec3 TransmittanceTable::toTop(double r, double mu) const {
    if (rayHitsGround(a_, std::clamp(r, a_.earthRadiusM, a_.topRadiusM), mu)) return glm::dvec3(0.0);
    return expNeg(opticalDepth(r, mu));
}

glm::dvec3 TransmittanceTable::sunlight(double r, double muSun) const {
    r = std::clamp(r, a_.earthRadiusM, a_.topRadiusM);
    // The horizon's cosine at r; the disc fades out as it sinks through it (Bruneton's smooth step).
    const double sinH = a_.earthRadiusM / r;
    const double cosH = -std::sqrt(std::max(0.0, 1.0 - sinH * sinH));
    const double visible = smoothstep(-sinH * a_.sunAngularRadius, sinH * a_.sunAngularRadius, muSun - cosH);
    if (visible <= 0.0) return glm::dvec3(0.0);
    return visible * expNeg(opticalDepth(r, std::max(muSun, cosH)));
}

// ---- Reference single scattering -----------------------------------------------------------------------------

glm::dvec3 referenceRadiance(const AtmosphereParameters& a, double altitudeM, const glm::dvec3& view,
                             const glm::dvec3& sun, int steps, double maxDistanceM) {
    const double R = a.earthRadiusM;
    const glm::dvec3 p0{0.0, 0.0, R + altitudeM};
    const double r0 = p0.z, mu = view.z;
    const bool ground = rayHitsGround(a, r0, mu);
    const double dEnd = ground ? distanceToGround(a, r0, mu) : distanceToTop(a, r0, mu);
    const double d = std::min(dEnd, maxDistanceM);
    // Midpoint rule on intervals that grow quadratically, fine near the viewer where the air is densest.
    glm::dvec3 tau(0.0), rayleigh(0.0), mie(0.0);
    double prev = 0.0;
    for (int i = 1; i <= steps; ++i) {
        const double s = double(i) / steps, t1 = d * s * s;
        const double dt = t1 - prev, t = 0.5 * (prev + t1);
        prev = t1;
        const glm::dvec3 p = p0 + t * view;
        const double r = glm::length(p), h = r - R;
        const glm::dvec3 ext = a.extinctionAt(h);
        const glm::dvec3 toViewer = expNeg(tau + 0.5 * dt * ext);
        tau += dt * ext;
        const double muSun = glm::dot(p, sun) / r;
        if (rayHitsGround(a, r, muSun)) continue;
        const glm::dvec3 sunT = expNeg(opticalDepthToTop(a, r, muSun, 256));
        rayleigh += toViewer * sunT * (std::exp(-h / a.rayleighScaleHeightM) * dt);
        mie += toViewer * sunT * (std::exp(-h / a.mieScaleHeightM) * dt);
    }
    const double nu = glm::dot(view, sun);
    glm::dvec3 l = a.rayleighScattering * rayleigh * rayleighPhase(nu) +
                   a.haze * a.mieScattering * mie * henyeyGreensteinPhase(nu, a.mieG);
    if (ground && dEnd <= maxDistanceM) {
        const glm::dvec3 pg = p0 + dEnd * view;
        const double muSun = glm::dot(glm::normalize(pg), sun);
        if (muSun > 0.0)
            l += expNeg(tau) * expNeg(opticalDepthToTop(a, R, muSun, 256)) * (a.groundAlbedo / kPi * muSun);
    }
    return l;
}

// ---- Sky tables ------------------------------------------------------------------------------------------------
// Directions are tabulated by azimuth from the sun (0..pi) and elevation. Sky rows run from the viewer's horizon
// (the tangent to the Earth, below zero elevation for a viewer above the ground) to the zenith, ground rows from
// the horizon to the nadir, both with rows packed quadratically towards the horizon, where the sky changes fastest.
// Aerial perspective rows span the whole sphere, packed towards zero elevation, and its slices are distances
// packed quadratically towards the viewer.

SkyTables::SkyTables(std::shared_ptr<const TransmittanceTable> transmittance, double viewerAltitudeM,
                     const glm::dvec3& sun)
    : t_(std::move(transmittance)), a_(t_->parameters()) {
    altitudeM_ = std::clamp(viewerAltitudeM, 1.0, a_.topRadiusM - a_.earthRadiusM - 1.0);
    r_ = a_.earthRadiusM + altitudeM_;
    sun_ = glm::normalize(sun);
    const double sunFlat = std::hypot(sun_.x, sun_.y);
    sunFlat_ = sunFlat > 1e-12 ? glm::dvec2(sun_.x, sun_.y) / sunFlat : glm::dvec2(0.0, 1.0);
    horizonElevation_ = -std::acos(std::clamp(a_.earthRadiusM / r_, -1.0, 1.0));
    horizonZ_ = std::sin(horizonElevation_);

    // The unit direction of column c (cosine of the azimuth from the sun, 1 down to -1) and height z.
    auto direction = [&](int c, int columns, double z) {
        const double cosAz = 1.0 - 2.0 * c / (columns - 1), sinAz = std::sqrt(std::max(0.0, 1.0 - cosAz * cosAz));
        const glm::dvec2 flat = cosAz * sunFlat_ + sinAz * glm::dvec2(sunFlat_.y, -sunFlat_.x);
        const double rxy = std::sqrt(std::max(0.0, 1.0 - z * z));
        return glm::dvec3(rxy * flat, z);
    };
    // Under ranks sharing their work (ranks::SharedWork), rank r fills the columns c with c mod K = r and the
    // others stay zero until the sum over the ranks completes them.
    const ranks::WorkShare share = ranks::workShare();
    sky_.resize(size_t(kAzimuthSize) * kSkyRows);
    ground_.resize(size_t(kAzimuthSize) * kGroundRows);
    tbb::parallel_for(0, kAzimuthSize, [&](int c) {
        if (!share.mine(c)) return;
        for (int k = 0; k < kSkyRows; ++k)
            sky_[size_t(k) * kAzimuthSize + size_t(c)] =
                march(direction(c, kAzimuthSize, zOfRow(k, false, kSkyRows)), 1e30, 64, nullptr);
        for (int k = 0; k < kGroundRows; ++k)
            ground_[size_t(k) * kAzimuthSize + size_t(c)] =
                march(direction(c, kAzimuthSize, zOfRow(k, true, kGroundRows)), 1e30, 64, nullptr);
    });
    aerial_.resize(size_t(kAerialAzimuth) * kAerialRows * kAerialSlices);
    tbb::parallel_for(0, kAerialAzimuth, [&](int c) {
        if (!share.mine(c)) return;
        std::vector<Texel> slices;
        for (int k = 0; k < kAerialRows; ++k) {
            const double x = 2.0 * k / (kAerialRows - 1) - 1.0;
            march(direction(c, kAerialAzimuth, x * std::abs(x)), kAerialMaxM, 0, &slices);
            std::copy(slices.begin(), slices.end(),
                      aerial_.begin() + ptrdiff_t((size_t(k) * kAerialAzimuth + size_t(c)) * kAerialSlices));
        }
    });
    if (share.shared) {
        // Every entry is zero or positive (radiances, optical depths), and x + 0 = x for those: each entry comes out
        // as the one rank that computed it made it.
        static_assert(sizeof(Texel) == 9 * sizeof(float), "a texel is nine floats");
        for (std::vector<Texel>* table : {&sky_, &ground_, &aerial_})
            ranks::sumFloats(reinterpret_cast<float*>(table->data()), table->size() * 9);
    }
}

// Rows by the height z of the unit direction: a hair off the tangent itself, so that the horizon rows see sky and
// ground as their side of it does.
double SkyTables::zOfRow(double row, bool ground, int rows) const {
    const double x = row / (rows - 1), eps = 1e-7;
    if (ground) return horizonZ_ - eps - (horizonZ_ - eps + 1.0) * x * x;
    return horizonZ_ + eps + (1.0 - horizonZ_ - eps) * x * x;
}

double SkyTables::rowOfZ(double z, bool ground, int rows) const {
    const double eps = 1e-7;
    const double x = ground ? std::sqrt(std::max(0.0, (horizonZ_ - eps - z) / (horizonZ_ - eps + 1.0)))
                            : std::sqrt(std::max(0.0, (z - horizonZ_ - eps) / (1.0 - horizonZ_ - eps)));
    return std::min(1.0, x) * (rows - 1);
}

// Marches from the viewer along `view` to the top of the atmosphere, the ground or `maxDistanceM`. With `slices`
// it records the running integrals at the aerial-perspective distances instead (substeps between them).
SkyTables::Texel SkyTables::march(const glm::dvec3& view, double maxDistanceM, int steps,
                                  std::vector<Texel>* slices) const {
    const double R = a_.earthRadiusM;
    const glm::dvec3 p0{0.0, 0.0, r_};
    const bool ground = rayHitsGround(a_, r_, view.z);
    const double dEnd = ground ? distanceToGround(a_, r_, view.z) : distanceToTop(a_, r_, view.z);
    glm::dvec3 tau(0.0), rayleigh(0.0), mie(0.0);
    auto integrate = [&](double from, double to) {
        const double lo = std::min(from, dEnd), hi = std::min(to, dEnd);
        if (hi <= lo) return;
        const double dt = hi - lo, t = 0.5 * (lo + hi);
        const glm::dvec3 p = p0 + t * view;
        const double r = glm::length(p), h = r - R;
        const glm::dvec3 ext = a_.extinctionAt(h);
        const glm::dvec3 toViewer = expNeg(tau + 0.5 * dt * ext);
        tau += dt * ext;
        const glm::dvec3 sunT = t_->sunlight(r, glm::dot(p, sun_) / r);
        if (sunT == glm::dvec3(0.0)) return;
        rayleigh += toViewer * sunT * (std::exp(-h / a_.rayleighScaleHeightM) * dt);
        mie += toViewer * sunT * (std::exp(-h / a_.mieScaleHeightM) * dt);
    };
    Texel out;
    if (slices) {
        constexpr int kSubsteps = 4;
        slices->assign(size_t(kAerialSlices), Texel{glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)});
        double prev = 0.0;
        for (int k = 1; k < kAerialSlices; ++k) {
            const double s = double(k) / (kAerialSlices - 1), d = maxDistanceM * s * s;
            for (int q = 1; q <= kSubsteps; ++q) {
                const double t1 = prev + (d - prev) * q / kSubsteps, t0 = prev + (d - prev) * (q - 1) / kSubsteps;
                integrate(t0, t1);
            }
            prev = d;
            (*slices)[size_t(k)] = {glm::vec3(rayleigh), glm::vec3(mie), glm::vec3(tau)};
        }
        return out;
    }
    const double d = std::min(dEnd, maxDistanceM);
    double prev = 0.0;
    for (int i = 1; i <= steps; ++i) {
        const double s = double(i) / steps, t1 = d * s * s;
        integrate(prev, t1);
        prev = t1;
    }
    out.rayleigh = glm::vec3(rayleigh);
    out.mie = glm::vec3(mie);
    out.extra = glm::vec3(0.0f);
    if (ground && dEnd <= maxDistanceM) {
        const glm::dvec3 pg = p0 + dEnd * view;
        const double muSun = glm::dot(glm::normalize(pg), sun_);
        if (muSun > 0.0) out.extra = glm::vec3(expNeg(tau) * t_->sunlight(R, muSun) * (a_.groundAlbedo / kPi * muSun));
    }
    return out;
}

// The column coordinate in [0, 1] (from the sun's azimuth to the opposite one; the sky is symmetric about the
// sun's vertical plane, so every quantity is smooth in the azimuth's cosine), z and nu of a unit direction.
void SkyTables::angles(const glm::dvec3& d, double& column, double& z, double& nu) const {
    const double flat2 = d.x * d.x + d.y * d.y;
    const double cosAz = flat2 > 1e-24 ? (d.x * sunFlat_.x + d.y * sunFlat_.y) / std::sqrt(flat2) : 1.0;
    column = std::clamp(0.5 - 0.5 * cosAz, 0.0, 1.0);
    z = std::clamp(d.z, -1.0, 1.0);
    nu = glm::dot(d, sun_);
}

glm::vec3 SkyTables::combine(const Texel& t, double nu) const {
    const glm::vec3 betaR(a_.rayleighScattering);
    const float pr = float(rayleighPhase(nu));
    const float pm = float(a_.haze * a_.mieScattering * henyeyGreensteinPhase(nu, a_.mieG));
    return betaR * t.rayleigh * pr + t.mie * pm;
}

namespace {
template <class T>
T lerp2(const T& a, const T& b, const T& c, const T& d, float u, float v) {
    return (1.0f - v) * ((1.0f - u) * a + u * b) + v * ((1.0f - u) * c + u * d);
}
}  // namespace

glm::vec3 SkyTables::radiance(const glm::dvec3& dir) const {
    double col, z, nu;
    angles(dir, col, z, nu);
    const bool ground = z < horizonZ_;
    const int rows = ground ? kGroundRows : kSkyRows;
    const std::vector<Texel>& table = ground ? ground_ : sky_;
    const double fx = col * (kAzimuthSize - 1), fy = rowOfZ(z, ground, rows);
    const int i = std::min(int(fx), kAzimuthSize - 2), j = std::min(int(fy), rows - 2);
    const float u = float(fx - i), v = float(fy - j);
    auto at = [&](int ii, int jj) -> const Texel& { return table[size_t(jj) * kAzimuthSize + size_t(ii)]; };
    const Texel &t00 = at(i, j), &t10 = at(i + 1, j), &t01 = at(i, j + 1), &t11 = at(i + 1, j + 1);
    const Texel t{lerp2(t00.rayleigh, t10.rayleigh, t01.rayleigh, t11.rayleigh, u, v),
                  lerp2(t00.mie, t10.mie, t01.mie, t11.mie, u, v),
                  lerp2(t00.extra, t10.extra, t01.extra, t11.extra, u, v)};
    return combine(t, nu) + t.extra;
}

void SkyTables::aerial(const glm::dvec3& dir, double distanceM, glm::vec3& transmittance,
                       glm::vec3& inscattered) const {
    double col, z, nu;
    angles(dir, col, z, nu);
    const double x = std::copysign(std::sqrt(std::abs(z)), z);
    const double fx = col * (kAerialAzimuth - 1), fy = (0.5 * x + 0.5) * (kAerialRows - 1);
    // Slices sit at quadratic distances; between two, the integrals grow about linearly with distance.
    const double slice = std::sqrt(std::clamp(distanceM / kAerialMaxM, 0.0, 1.0)) * (kAerialSlices - 1);
    const int i = std::min(int(fx), kAerialAzimuth - 2), j = std::clamp(int(fy), 0, kAerialRows - 2);
    const int k = std::min(int(slice), kAerialSlices - 2);
    const double s0 = double(k) / (kAerialSlices - 1), s1 = double(k + 1) / (kAerialSlices - 1);
    const double d0 = kAerialMaxM * s0 * s0, d1 = kAerialMaxM * s1 * s1;
    const float u = float(fx - i), v = float(std::clamp(fy - j, 0.0, 1.0));
    const float w = float(std::clamp((distanceM - d0) / (d1 - d0), 0.0, 1.0));
    auto at = [&](int ii, int jj, int kk) -> const Texel& {
        return aerial_[(size_t(jj) * kAerialAzimuth + size_t(ii)) * kAerialSlices + size_t(kk)];
    };
    Texel s[2];
    for (int q = 0; q < 2; ++q) {
        const Texel &t00 = at(i, j, k + q), &t10 = at(i + 1, j, k + q), &t01 = at(i, j + 1, k + q),
                    &t11 = at(i + 1, j + 1, k + q);
        s[q] = {lerp2(t00.rayleigh, t10.rayleigh, t01.rayleigh, t11.rayleigh, u, v),
                lerp2(t00.mie, t10.mie, t01.mie, t11.mie, u, v), lerp2(t00.extra, t10.extra, t01.extra, t11.extra, u, v)};
    }
    const Texel t{glm::mix(s[0].rayleigh, s[1].rayleigh, w), glm::mix(s[0].mie, s[1].mie, w),
                  glm::mix(s[0].extra, s[1].extra, w)};
    // Optical depth interpolates far better than transmittance where the air thickens quickly.
    transmittance = glm::vec3(std::exp(-t.extra.x), std::exp(-t.extra.y), std::exp(-t.extra.z));  // float exp
    inscattered = combine(t, nu);
}

}  // namespace terracast
