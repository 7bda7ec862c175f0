// The texture rule.
//
// Saliency lights up what is bright or different: a specular highlight, a shadow, a flat patch
// of colour stand out as much as a logo does. What a person protects is structure: lettering,
// a pattern, a badge, eyes, i.e. detail that a deformation would visibly bend. Detail is
// measured as edge density, the fraction of a region's pixels on Canny edges of the grey work
// image blurred by a pixel (JPEG noise and film grain are not structure). Three tests, each
// against a way saliency fails:
//
// - Denser than the object (kTextureRatio times the density over the whole polygon): a
//   highlight or a shadow is smooth inside, its one soft edge a small fraction of its area; on
//   a plain fruit nothing passes.
// - Denser than its surroundings (the same ratio against a ring around the region, as wide as
//   its equivalent radius): fur on a furry animal, the rim of a collar on a textured suit or a
//   table edge under a smooth fruit (denser than the fruit, not than the table around it) are
//   the texture of where they sit, not a feature in it. Lettering on a shirt, an eye in fur,
//   windows on a wall stand out from what is around them.
// - Small (at most kFeatureShare of the polygon): a feature is a detail of its object; a salient
//   region a tenth of the object or more (the inside of a cup, a bird's breast) is a part of
//   the object, which deforms with it.
#include "texture.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgproc.hpp>

#include "segment.hpp"

namespace cv {
namespace multicage {
namespace propose_detail {

Mat textureEdges(const Mat& img, const Work& w) {
    Mat gray = toWork(to8Bit(img), w, INTER_AREA);
    if (gray.channels() == 3) cvtColor(gray, gray, COLOR_BGR2GRAY);
    if (gray.channels() == 4) cvtColor(gray, gray, COLOR_BGRA2GRAY);
    GaussianBlur(gray, gray, Size(), 1.0);
    Mat edges;
    Canny(gray, edges, 40, 100, 3, true);
    edges.convertTo(edges, CV_32F, 1.0 / 255);
    return edges;
}

namespace {

// Edge density of the ring around region `id` (component of `ids`, bounding box `box`, area
// `area`): as wide as the region's equivalent radius (at least 3 px), inside `inside`, outside
// every salient region. 0 when the ring is empty. Half as wide, the ring around a cartoon
// fish's eye was mostly the black stroke of its head (1.10 times the eye's density: dropped);
// one and a half times, the table's edge under the orange came back (1.34).
double surroundingDensity(const Mat& edges, const Mat& ids, int id, const Rect& box, int area,
                          const Mat& inside) {
    const int r = std::max(3, cvRound(std::sqrt(area / CV_PI)));
    const Rect roi = Rect(box.x - r, box.y - r, box.width + 2 * r, box.height + 2 * r) &
                     Rect(Point(), ids.size());
    const Mat region = ids(roi) == id;
    // The pixels within r of the region: a threshold of the distance to it costs the same
    // for every r, where a dilation by a disk of radius r costs r rows per pixel (a fifth of
    // the proposal's time on the baboon's large fur regions).
    Mat ring = distanceTo(~region) <= r;
    ring &= (ids(roi) == 0) & inside(roi);
    return countNonZero(ring) > 0 ? mean(edges(roi), ring)[0] : 0.0;
}

}  // namespace

Mat texturedOnly(const Mat& objects, const Mat& edges, const Mat& inside, bool plainSurroundings) {
    const double object = mean(edges, inside)[0];
    const double insideArea = countNonZero(inside);
    Mat ids, stats, centroids;
    const int n = connectedComponentsWithStats(objects, ids, stats, centroids, 8, CV_32S);
    std::vector<double> sum(n, 0.0);
    for (int y = 0; y < ids.rows; ++y)
        for (int x = 0; x < ids.cols; ++x) sum[ids.at<int>(y, x)] += edges.at<float>(y, x);
    std::vector<char> keep(n, 0);
    const bool debug = std::getenv("MULTICAGE_DEBUG_TEXTURE") != nullptr;
    for (int i = 1; i < n; ++i) {
        const int area = std::max(1, stats.at<int>(i, CC_STAT_AREA));
        const Rect box(stats.at<int>(i, CC_STAT_LEFT), stats.at<int>(i, CC_STAT_TOP),
                       stats.at<int>(i, CC_STAT_WIDTH), stats.at<int>(i, CC_STAT_HEIGHT));
        const double density = sum[i] / area;
        const double around = surroundingDensity(edges, ids, i, box, area, inside);
        const double share = area / std::max(1.0, insideArea);
        keep[i] = density >= kTextureRatio * object && density >= kTextureRatio * around &&
                  share <= kFeatureShare && (!plainSurroundings || around <= object);
        if (debug)
            std::fprintf(stderr,
                         "texture: region %d at %d,%d area %d (%.3f of the polygon): %.2f of the "
                         "object's density, %.2f of its surroundings': %s\n",
                         i, box.x, box.y, area, share, density / std::max(1e-9, object),
                         density / std::max(1e-9, around), keep[i] ? "kept" : "dropped");
    }
    Mat out = objects.clone();
    for (int y = 0; y < ids.rows; ++y)
        for (int x = 0; x < ids.cols; ++x)
            if (!keep[ids.at<int>(y, x)]) out.at<uchar>(y, x) = 0;
    return out;
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv
