// Mean value weights of one point, in double precision (private).
#ifndef MULTICAGE_MEAN_VALUE_HPP
#define MULTICAGE_MEAN_VALUE_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace multicage {

/** Where a point lies relative to a polygon, as far as mean value coordinates care. */
enum class MeanValueCase {
    General,   //!< w holds the raw weights w_i = (t_{i-1} + t_i) / r_i
    OnVertex,  //!< w holds 1 at the vertex, 0 elsewhere (exact Lagrange property)
    OnEdge     //!< w holds the edge's linear interpolation, 0 elsewhere
};

/** Raw mean value weights of x for polygon v[0..n) (Hormann & Floater 2006, eq. 7 with the
tan(alpha/2) formula of their §5). t_i is taken as A_i / (r_i r_{i+1} + D_i) where D_i > 0 and
as (r_i r_{i+1} - D_i) / A_i elsewhere: the two are equal, and each is stable where the
other divides 0 by 0. */
MeanValueCase meanValueWeights(const Point2d* v, int n, Point2d x, double* w);

}  // namespace multicage
}  // namespace cv

#endif
