// sampling/separation.h — the Uniform Separation of the hemisphere (normal +Z) from Penzov, Dimov,
// Sirakova and Koylazov: 8 orthogonal spherical triangles T_i around the normal (the central projection
// of the cube's top face, cut by its diagonals and medians) and 8 spherical quadrangles Q_i between
// them and the horizon. Piece i lies in azimuth octant i, [i pi/4, (i+1) pi/4]. Here: membership,
// solid angles, the 8 signed permutations, the paper's maps exactly as printed, our exact maps with
// closed-form densities, and the rotation that carries the triangles onto the Phong lobe.
#pragma once

#include "math/vec3.h"
#include "sampling/rng.h"

#include <cmath>

namespace symphong::separation {

/// atan(1/sqrt(2)) = acos(sqrt(2/3)): the arc from the face centre's edge midpoint to its corner, seen
/// from the sphere's centre; appears in every closed form below.
inline const double kA = std::atan(1.0 / std::sqrt(2.0));

/// Solid angle of one triangle T_i: the cube face subtends 4 pi / 6, cut into 8.   |T_i| = pi/12.
inline constexpr double kTriangleSolidAngle = kPi / 12.0;
/// Solid angle of one quadrangle Q_i: (2 pi - 8 pi/12) / 8.   |Q_i| = pi/6.
inline constexpr double kQuadrangleSolidAngle = kPi / 6.0;
/// Projected solid angle of T_0, int cos(theta) dw, by Lambert's polygon formula: only the edge
/// from (1,0,1) to (1,1,1) contributes, (1/2) * kA * (1/sqrt 2):   Phi_T = kA / (2 sqrt 2) = 0.217605.
inline const double kTriangleProjected = kA / (2.0 * std::sqrt(2.0));
/// Projected solid angle of Q_0: the octant's pi/8 less the triangle's:  Phi_Q = pi/8 - Phi_T = 0.175094.
inline const double kQuadrangleProjected = kPi / 8.0 - kTriangleProjected;

enum class PieceKind { Triangle, Quadrangle };

struct Piece {
    PieceKind kind = PieceKind::Triangle;
    int octant = 0;  ///< 0..7, azimuth [octant pi/4, (octant+1) pi/4]
};

/// The signed permutation of (x, y) that maps octant 0 (0 <= phi <= pi/4) onto octant k, z unchanged:
///   k: 0 (x,y)  1 (y,x)  2 (-y,x)  3 (-x,y)  4 (-x,-y)  5 (-y,-x)  6 (y,-x)  7 (x,-y)
/// i.e. phi -> phi, pi/2 - phi, pi/2 + phi, pi - phi, pi + phi, 3pi/2 - phi, 3pi/2 + phi, 2pi - phi.
/// These are the paper's symmetric twins P_0..P_7 ("change of the signs and/or places of X0 and Y0").
inline Vec3 toOctant(const Vec3& w, int k) {
    switch (k & 7) {
        case 0:
            return {w.x, w.y, w.z};
        case 1:
            return {w.y, w.x, w.z};
        case 2:
            return {-w.y, w.x, w.z};
        case 3:
            return {-w.x, w.y, w.z};
        case 4:
            return {-w.x, -w.y, w.z};
        case 5:
            return {-w.y, -w.x, w.z};
        case 6:
            return {w.y, -w.x, w.z};
        default:
            return {w.x, -w.y, w.z};
    }
}

/// Octant of a direction's azimuth, 0..7 (phi = atan2(y, x) in [0, 2 pi)).
int octantOf(const Vec3& w);

/// Folds a direction into octant 0 by the inverse signed permutation: (max(|x|,|y|), min(|x|,|y|), z).
inline Vec3 foldToOctant0(const Vec3& w) {
    const double ax = std::abs(w.x), ay = std::abs(w.y);
    return {std::max(ax, ay), std::min(ax, ay), w.z};
}

/// Whether w lies in the union of the triangles, T = { max(|x|,|y|) <= z } (tan(theta) cos(phi) <= 1 in
/// octant 0): the projection of the cube face z = 1.
inline bool inTriangles(const Vec3& w) { return std::max(std::abs(w.x), std::abs(w.y)) <= w.z; }

/// The piece that holds w (upper hemisphere). Every direction with z > 0 is in exactly one piece, up to
/// the measure-zero seams, which go to the lower octant and to the triangle.
Piece pieceOf(const Vec3& w);

// ---------------------------------------------------------------------------------------------------
// The paper's maps, exactly as printed (section "Monte Carlo estimator").

/// Paper's triangle map:  phi = u pi/4,  theta = arctan(v / cos(phi)).  Onto T_0 (checked); on the
/// plane z = 1 it is x = v, y = v tan(phi).
Vec3 paperTriangleMap(Point2 p);
/// Paper's quadrangle map as printed:  phi = u pi/4,  theta = arccot(v / cos(phi)).  Wrong (erratum 2):
/// it maps onto theta in [arctan(cos phi), pi/2], the mirror image of the triangle, not onto Q_0.
Vec3 paperQuadrangleMap(Point2 p);
/// The paper's Jacobian weight  w(u,v) = v cos^2(u pi/4) / (v^2 + cos^2(u pi/4))^2, with
/// cos(theta) dw = (pi/4) w(u,v) du dv for the triangle map.
double paperWeight(Point2 p);

// ---------------------------------------------------------------------------------------------------
// Our exact maps, uniform in projected solid angle inside each piece (so a constant radiance gives a
// zero-variance diffuse estimate), derived in docs/estimators.md. Projected onto the unit disk
// (x, y) = sin(theta) (cos phi, sin phi), T_0 is the wedge 0 <= phi <= pi/4, rho <= rho_T(phi) with
// rho_T(phi)^2 = 1 / (1 + cos^2 phi), and Q_0 the rest of the wedge out to rho = 1; uniform area there is
// uniform projected solid angle on the sphere (Malley).

/// rho_T(phi)^2 = 1 / (1 + cos^2 phi): the triangle's edge tan(theta) cos(phi) = 1 on the unit disk.
inline double triangleEdgeRho2(double phi) {
    const double c = std::cos(phi);
    return 1.0 / (1.0 + c * c);
}

/// Triangle: the wedge's area up to phi is (1/(2 sqrt 2)) atan(tan(phi)/sqrt 2), so
///   phi = atan(sqrt(2) tan(u kA)),   rho^2 = v rho_T(phi)^2.      p(w) = cos(theta) / Phi_T on T_0.
Vec3 triangleMap(Point2 p);
/// Quadrangle: the area between rho_T and 1 up to phi is G(phi) = (phi - atan(tan(phi)/sqrt 2)/sqrt 2) / 2;
///   phi = G^-1(u Phi_Q) (Newton's method, to round-off),   rho^2 = rho_T^2 + v (1 - rho_T^2).
///                                                               p(w) = cos(theta) / Phi_Q on Q_0.
Vec3 quadrangleMap(Point2 p);
/// Inverse of G on [0, pi/4], exposed for tests.
double quadrangleAzimuth(double area);
/// tan of quadrangleAzimuth(area), what the map uses: a cubic Hermite table of G^-1 in t = tan(phi)
/// and one Newton step on G(atan t) = area (two arctangents, no tangent or cosine).
double quadrangleTangent(double area);
/// Density of the piece's map at w (solid angle), w in that piece: cos(theta) / Phi_piece.
inline double pieceDensity(PieceKind kind, const Vec3& w) {
    return w.z / (kind == PieceKind::Triangle ? kTriangleProjected : kQuadrangleProjected);
}

/// Phong-lobe map of T_0 about its own axis +Z (for the rotated, specular triangles): phi = u pi/4 and,
/// on the plane z = 1 at distance s from the axis (cos(alpha) = 1/sqrt(1+s^2)), s distributed as
/// s (1+s^2)^(-(n+3)/2) up to the edge s_max = 1/cos(phi):
///   s^2 = (1 - v c(phi))^(-2/(n+1)) - 1,   c(phi) = 1 - (cos^2 phi / (1 + cos^2 phi))^((n+1)/2).
///   p(w) = (4/pi) (n+1) cos^n(alpha) / c(phi)   on T_0  (tends to 8 x the Phong lobe pdf as n grows).
Vec3 lobeTriangleMap(Point2 p, double n);
/// Its density at w in T_0 (w given in octant 0 of the lobe's frame).
double lobeTriangleDensity(const Vec3& w, double n);

// ---------------------------------------------------------------------------------------------------
// The pieces of `symmetric-mix` (docs/estimators.md, section 10): the diffuse pieces drawn in proportion
// to their projected solid angle, and the Phong lobe cut into 8 azimuth wedges instead of the cube face.

/// Share of the triangle in its octant's projected solid angle:  Phi_T / (pi/8) = 0.554126. Drawing the
/// triangle with this probability and the quadrangle with 1 - kTriangleShare, each by its exact map, is
/// cosine sampling of the octant (p = cos(theta) / (pi/8) = 8 cos(theta)/pi on the octant); the 8
/// octants by symmetry make it cosine sampling of the hemisphere (cause 1 of the symmetric-mix issue).
inline const double kTriangleShare = kTriangleProjected / (kPi / 8.0);

/// Cosine-weighted direction in octant 0 from one point: the triangle with probability kTriangleShare
/// (u rescaled onto [0,1) inside its share), else the quadrangle, each by its exact map.
///   p(w) = 8 cos(theta) / pi  on octant 0 (T_0 u Q_0).
Vec3 octantCosineMap(Point2 p);

/// Wedge 0 (azimuth 0..pi/4 about the lobe axis +Z) of the exact Phong lobe:
///   phi = u pi/4,   cos(alpha) = v^(1/(n+1))   (the CDF of cos^n(alpha) sin(alpha) on [0, pi/2]).
///   p(w) = 8 (n+1)/(2 pi) cos^n(alpha)  on the wedge: the lobe's density, times 8 for the wedge's share.
/// Unlike the cube-face triangles (erratum 5) the 8 wedges cover the whole lobe, at every n.
Vec3 phongWedgeMap(Point2 p, double n);

// ---------------------------------------------------------------------------------------------------
// Carrying the triangles onto the lobe (Eq. 6 and the rotation that follows it).

/// The local frame turned about the normal so that the mirror direction r lies in the (Y,Z) plane at
/// (0, -sin theta_s, cos theta_s); then R_X(theta_s) carries +Z onto r. When r is the normal, the
/// frame is the local one.
struct LobeFrame {
    Vec3 ex, ey;                ///< turned X and Y axes in the local frame (Z is the normal)
    double cosS = 1, sinS = 0;  ///< cos and sin of theta_s, the angle between normal and r

    static LobeFrame fromMirror(const Vec3& r);
    /// R_X(theta_s):  (X, Y cos - Z sin, Z cos + Y sin)  (the paper's rotation matrix), then to local.
    Vec3 toLocal(const Vec3& faceDir) const;
    /// Inverse: local direction -> the triangle face's frame (axis +Z = r).
    Vec3 toFace(const Vec3& local) const;
};

}  // namespace symphong::separation
