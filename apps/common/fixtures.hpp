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
std::vector<cv::Point2f> stretchPolygon(const cv::multicage::Multicage& cage, int polygon, float sx,
                                        float sy, cv::Point2f shift = {});

/** A smooth random pose: every user vertex moved by a displacement field of amplitude
`amplitude` pixels (so nested polygons stay nested for moderate amplitudes). */
std::vector<cv::Point2f> wavePose(const cv::multicage::Multicage& cage, float amplitude,
                                  float phase = 0.f);

/** Mean distance (px) from `moved` to the least-squares similarity of `rest` onto it (what
remains when a rotation, a uniform scale and a translation are taken out): 0 for a rigid
motion plus uniform scale. Infinity for fewer than 2 points or coincident rest points. */
double similarityResidual(const std::vector<cv::Point2f>& rest,
                          const std::vector<cv::Point2f>& moved);

/** The binding's grid nodes inside the middle `inner` fraction of `box` (0.8: the box's inner
80%, which leaves out the hair and background a detector's box holds at its edges). */
std::vector<cv::Point2f> boxNodes(const cv::multicage::Binding& binding, const cv::Rect2d& box,
                                  double inner = 0.8);

/** How far a box's content is from a similarity under `pose`: similarityResidual() over the
grid nodes of boxNodes(binding, box, inner) and where the binding moves them. The measure of
"a face stays a face" (the demo, the tests and the proposal benchmark all use it). Infinity
when fewer than 3 nodes lie in the box. */
double boxResidual(const cv::multicage::Binding& binding, const std::vector<cv::Point2f>& pose,
                   const cv::Rect2d& box, double inner = 0.8);

/** Pixels inside a polygon (vertices rounded to the nearest pixel), 255 on 0, of `size`: the
mask the proposal benchmark and its tests score outlines with. */
cv::Mat polygonMask(const std::vector<cv::Point2f>& polygon, cv::Size size);

/** The inner polygons (depth 2 or more) of cage that hold at least 95% of the ellipse
inscribed in an eye's box (an eye is an almond: a box's corners are skin) and are at most 3
times the box's area. The eye is hugged when exactly one does (the proposal benchmark and its
tests). */
std::vector<int> eyeHolders(const cv::multicage::Multicage& cage, const cv::Rect& eye);

/** The inner polygons (depth 2 or more) of cage that hold at least 95% of a face box's inner
80% and are at most 3 times the box's area. The face is hugged when exactly one does (the
proposal benchmark and its tests). */
std::vector<int> faceHolders(const cv::multicage::Multicage& cage, const cv::Rect& face);

/** The inner polygons (depth 2 or more) of cage that hold at least 90% of a feature's box (a
badge, a name tag, lettering) and are at most 4 times its area: the feature is protected when
one does (issue 39, item 4; the proposal benchmark and its tests). */
std::vector<int> featureHolders(const cv::multicage::Multicage& cage, const cv::Rect& feature);

/** The outline (depth-1 polygon) of cage holding the centre of box, or -1: the polygon a
face's scores are measured against. */
int outlineAround(const cv::multicage::Multicage& cage, const cv::Rect& box);

}  // namespace multicage_fixtures

#endif
