#include "scene/environment_map.h"

#include <cmath>

namespace symphong {

const char* filterName(EnvironmentMap::Filter filter) { return filter == EnvironmentMap::Filter::Nearest ? "nearest" : "bilinear"; }

EnvironmentMap::EnvironmentMap(Texture image, double scale, double rotationDegrees, Filter filter)
    : image_(std::move(image)), scale_(scale), rotation_(rotationDegrees), filter_(filter) {
    image_.wrapU = WrapMode::Repeat;  // round the sphere
    image_.wrapV = WrapMode::Clamp;   // not over the poles
    const int w = image_.width(), h = image_.height();
    std::vector<double> weights(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    luminanceIntegral_ = 0;
    std::vector<double> lum(weights.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            lum[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] =
                scale_ * luminance(image_.texelRgb(x, y));
    const auto at = [&](int x, int y) {
        return lum[static_cast<std::size_t>(wrapIndex(y, h, WrapMode::Clamp)) * static_cast<std::size_t>(w) +
                   static_cast<std::size_t>(wrapIndex(x, w, WrapMode::Repeat))];
    };
    for (int y = 0; y < h; ++y) {
        // Texel (x, y) covers theta in [pi y / H, pi (y+1) / H]: its density over the image is made
        // proportional to Y x sin(theta at its centre), so the solid-angle density is close to Y. Under
        // bilinear filtering, Y is the mean of the filtered luminance over the texel's area: its 3 x 3
        // neighbourhood weighted 1/8, 3/4, 1/8 along each axis (the mean of a hat-function interpolant over
        // one cell), so a bright texel's blurred rim is sampled too and shows no fireflies.
        const double sinTheta = std::sin(kPi * (y + 0.5) / h);
        const double solidAngle = texelSolidAngle(y);
        for (int x = 0; x < w; ++x) {
            double y0 = at(x, y);
            luminanceIntegral_ += y0 * solidAngle;
            if (filter_ == Filter::Bilinear) {
                static constexpr double kWeight[3] = {0.125, 0.75, 0.125};
                y0 = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) y0 += kWeight[dx + 1] * kWeight[dy + 1] * at(x + dx, y + dy);
            }
            weights[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] = y0 * sinTheta;
        }
    }
    distribution_ = Distribution2D(weights, static_cast<std::size_t>(w), static_cast<std::size_t>(h));
}

double EnvironmentMap::texelSolidAngle(int y) const {
    const int h = image_.height();
    return kTwoPi / image_.width() * (std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h));
}

void EnvironmentMap::toImage(const Vec3& d, double& u, double& t) const {
    const double theta = std::acos(std::clamp(d.y, -1.0, 1.0));
    const double phi = std::atan2(d.x, -d.z);
    u = 0.5 + phi / kTwoPi - rotation_ / 360.0;
    u -= std::floor(u);
    t = theta / kPi;
}

Vec3 EnvironmentMap::fromImage(double u, double t) const {
    const double phi = kTwoPi * (u - 0.5 + rotation_ / 360.0), theta = kPi * t;
    const double s = std::sin(theta);
    return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

Color EnvironmentMap::radiance(const Vec3& d) const {
    double u, t;
    toImage(d, u, t);
    return radianceAt(u, t);
}

Color EnvironmentMap::radianceAt(double u, double t) const {
    if (filter_ == Filter::Bilinear) return image_.rgb(u, 1.0 - t) * scale_;
    int x, y;
    image_.nearestTexel(u, 1.0 - t, x, y);
    return image_.texelRgb(x, y) * scale_;
}

// Density over the image p(u, t) = cellPdf; dw = 2 pi^2 sin(theta) du dt, so p(w) = p(u, t) / (2 pi^2 sin theta).
Vec3 EnvironmentMap::sample(Point2 u, double& pdf) const {
    pdf = 0;
    if (!(distribution_.total() > 0)) return {0, 1, 0};
    std::size_t x, y;
    double imagePdf;
    const Point2 p = distribution_.sample(u, x, y, imagePdf);
    const double sinTheta = std::sin(kPi * p.v);
    if (!(sinTheta > 0) || !(imagePdf > 0)) return {0, 1, 0};
    pdf = imagePdf / (2 * kPi * kPi * sinTheta);
    return fromImage(p.u, p.v);
}

double EnvironmentMap::pdf(const Vec3& d) const {
    if (!(distribution_.total() > 0)) return 0;
    double u, t;
    toImage(d, u, t);
    return pdfAt(u, t);
}

Color EnvironmentMap::radianceAndPdf(const Vec3& d, double& pdf) const {
    double u, t;
    toImage(d, u, t);
    pdf = distribution_.total() > 0 ? pdfAt(u, t) : 0.0;
    return radianceAt(u, t);
}

double EnvironmentMap::pdfAt(double u, double t) const {
    const double sinTheta = std::sin(kPi * t);
    if (!(sinTheta > 0)) return 0;
    int x, y;
    image_.nearestTexel(u, 1.0 - t, x, y);
    return distribution_.cellPdf(static_cast<std::size_t>(x), static_cast<std::size_t>(y)) / (2 * kPi * kPi * sinTheta);
}

}  // namespace symphong
