// scene/environment_map.h — an environment given as an HDR lat-long (equirectangular) image: the radiance
// arriving from every direction that leaves the scene, and its importance sampling for light sampling
// (texel luminance x sin(theta), sampling/distribution2d.h), which the path tracer combines by MIS with
// whatever estimator renders (render/path_tracer).
//
// Mapping, +Y up: theta = acos(d.y) from the zenith, phi = atan2(d.x, -d.z); the image's column
// coordinate is u = 1/2 + phi / (2 pi) - rotation / 360 (the image's centre looks along -Z, the default
// camera's view direction) and its row coordinate theta / pi from the top row (the zenith) to the bottom
// (the nadir).
#pragma once

#include "math/vec3.h"
#include "sampling/distribution2d.h"
#include "texture/texture.h"

#include <string>

namespace symphong {

class EnvironmentMap {
public:
    enum class Filter { Nearest, Bilinear };

    /// image: linear RGB (an alpha channel is ignored); radiance = scale x texel. Nearest filtering shows
    /// each texel as a constant patch of the sphere (what is sampled is exactly what is seen); bilinear
    /// blends neighbours (smoother to look at; MIS keeps it unbiased).
    EnvironmentMap(Texture image, double scale, double rotationDegrees, Filter filter);

    Color radiance(const Vec3& d) const;
    /// A direction with solid-angle density `pdf`, from uniform u; pdf 0 when the map is black.
    Vec3 sample(Point2 u, double& pdf) const;
    /// Solid-angle density of sample() for unit direction d.
    double pdf(const Vec3& d) const;
    /// radiance(d) and pdf(d) (as `pdf`) from one mapping of d onto the image (an acos and an atan2, the
    /// dearest part of either): the same values bit for bit.
    Color radianceAndPdf(const Vec3& d, double& pdf) const;
    /// Integral of the luminance of the radiance over the sphere, integral Y(L) dw (for choosing it
    /// among the scene's emitters in proportion to its power).
    double luminanceIntegral() const { return luminanceIntegral_; }

    const Texture& image() const { return image_; }
    double scale() const { return scale_; }
    double rotationDegrees() const { return rotation_; }
    Filter filter() const { return filter_; }
    /// The solid angle of texel row y: (2 pi / W) (cos theta_y - cos theta_{y+1}).
    double texelSolidAngle(int y) const;

    /// Image coordinates (column u in [0,1), row t in [0,1] from the top) of unit direction d, and back.
    void toImage(const Vec3& d, double& u, double& t) const;
    Vec3 fromImage(double u, double t) const;

private:
    /// radiance and pdf at image coordinates (u, t) of toImage (pdfAt: the distribution not empty).
    Color radianceAt(double u, double t) const;
    double pdfAt(double u, double t) const;

    Texture image_;
    double scale_ = 1, rotation_ = 0;
    Filter filter_ = Filter::Nearest;
    Distribution2D distribution_;
    double luminanceIntegral_ = 0;
};

const char* filterName(EnvironmentMap::Filter filter);

}  // namespace symphong
