// Multicages made from numbers, for benchmarks, tests and the demo (not part of the library).
#ifndef MULTICAGE_APPS_FIXTURES_HPP
#define MULTICAGE_APPS_FIXTURES_HPP

#include <opencv2/multicage.hpp>

namespace multicage_fixtures {

/** A star-shaped polygon around centre: vertex i at angle 2*pi*i/n and radius radii[i]. It
is simple whenever every radius is positive. Clockwise on screen (signed area > 0). */
std::vector<cv::Point2f> starPolygon(cv::Point2f centre, const std::vector<float>& radii,
                                     float phase = 0.f);

/** The paper's Table 1 shape: two "lotus flowers" side by side, each an outer polygon with a
protected inner polygon (4 polygons, depths 1 and 2), `vertices` user vertices in all
(at least 12), oriented. */
cv::multicage::Multicage lotusMulticage(cv::Size imageSize, int vertices);

/** A random valid, oriented multicage: up to maxTop top-level star polygons in disjoint
disks, each with nested children down to maxDepth, `perPolygon` vertices each (+-50%). */
cv::multicage::Multicage randomMulticage(cv::RNG& rng, cv::Size imageSize, int maxTop = 3,
                                         int maxDepth = 3, int perPolygon = 12);

/** A pose moving only polygon `polygon`'s vertices: scaled by (sx, sy) about its centroid
and shifted by `shift`. Every other vertex stays at rest. */
std::vector<cv::Point2f> stretchPolygon(const cv::multicage::Multicage& cage, int polygon,
                                        float sx, float sy, cv::Point2f shift = {});

/** A smooth random pose: every user vertex moved by a displacement field of amplitude
`amplitude` pixels (so nested polygons stay nested for moderate amplitudes). */
std::vector<cv::Point2f> wavePose(const cv::multicage::Multicage& cage, float amplitude,
                                  float phase = 0.f);

}  // namespace multicage_fixtures

#endif
