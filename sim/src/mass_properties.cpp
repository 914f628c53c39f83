// D. Eberly, "Polyhedral Mass Properties (Revisited)", Geometric Tools, 2002: the volume
// integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx over a polyhedron, from its faces.
#include <dawnforge/sim/mass_properties.hpp>

namespace dawnforge::sim {

namespace {

void subexpressions(double w0, double w1, double w2, double& f1, double& f2, double& f3, double& g0, double& g1,
                    double& g2) {
    const double temp0 = w0 + w1;
    f1 = temp0 + w2;
    const double temp1 = w0 * w0;
    const double temp2 = temp1 + w1 * temp0;
    f2 = temp2 + w2 * f1;
    f3 = w0 * temp1 + w1 * temp2 + w2 * f2;
    g0 = f2 + w0 * (f1 + w0);
    g1 = f2 + w1 * (f1 + w1);
    g2 = f2 + w2 * (f1 + w2);
}

}  // namespace

MassProperties computeMassProperties(std::span<const glm::dvec3> positions, std::span<const std::uint32_t> indices,
                                     double density) {
    MassProperties out;
    if (positions.empty() || indices.size() < 3) return out;
    // Integrate about the bounding-box centre: smaller numbers, less cancellation.
    glm::dvec3 lo = positions[0], hi = positions[0];
    for (const glm::dvec3& p : positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const glm::dvec3 origin = 0.5 * (lo + hi);

    double intg[10] = {};
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        const glm::dvec3 p0 = positions[indices[t]] - origin;
        const glm::dvec3 p1 = positions[indices[t + 1]] - origin;
        const glm::dvec3 p2 = positions[indices[t + 2]] - origin;
        const glm::dvec3 a = p1 - p0, b = p2 - p0;
        const double d0 = a.y * b.z - b.y * a.z, d1 = b.x * a.z - a.x * b.z, d2 = a.x * b.y - b.x * a.y;
        double f1x, f2x, f3x, g0x, g1x, g2x, f1y, f2y, f3y, g0y, g1y, g2y, f1z, f2z, f3z, g0z, g1z, g2z;
        subexpressions(p0.x, p1.x, p2.x, f1x, f2x, f3x, g0x, g1x, g2x);
        subexpressions(p0.y, p1.y, p2.y, f1y, f2y, f3y, g0y, g1y, g2y);
        subexpressions(p0.z, p1.z, p2.z, f1z, f2z, f3z, g0z, g1z, g2z);
        intg[0] += d0 * f1x;
        intg[1] += d0 * f2x;
        intg[2] += d1 * f2y;
        intg[3] += d2 * f2z;
        intg[4] += d0 * f3x;
        intg[5] += d1 * f3y;
        intg[6] += d2 * f3z;
        intg[7] += d0 * (p0.y * g0x + p1.y * g1x + p2.y * g2x);
        intg[8] += d1 * (p0.z * g0y + p1.z * g1y + p2.z * g2y);
        intg[9] += d2 * (p0.x * g0z + p1.x * g1z + p2.x * g2z);
    }
    constexpr double mult[10] = {1.0 / 6, 1.0 / 24, 1.0 / 24, 1.0 / 24, 1.0 / 60,
                                 1.0 / 60, 1.0 / 60, 1.0 / 120, 1.0 / 120, 1.0 / 120};
    for (int i = 0; i < 10; ++i) intg[i] *= mult[i];

    out.volume = intg[0];
    out.mass = intg[0] * density;
    if (intg[0] == 0.0) return out;
    const glm::dvec3 cm(intg[1] / intg[0], intg[2] / intg[0], intg[3] / intg[0]);
    out.centerOfMass = cm + origin;
    // Second moments about the centre of mass (parallel axis theorem), times density.
    const double xx = intg[5] + intg[6] - intg[0] * (cm.y * cm.y + cm.z * cm.z);
    const double yy = intg[4] + intg[6] - intg[0] * (cm.z * cm.z + cm.x * cm.x);
    const double zz = intg[4] + intg[5] - intg[0] * (cm.x * cm.x + cm.y * cm.y);
    const double xy = -(intg[7] - intg[0] * cm.x * cm.y);
    const double yz = -(intg[8] - intg[0] * cm.y * cm.z);
    const double xz = -(intg[9] - intg[0] * cm.z * cm.x);
    out.inertia = density * glm::dmat3(xx, xy, xz, xy, yy, yz, xz, yz, zz);
    return out;
}

}  // namespace dawnforge::sim
