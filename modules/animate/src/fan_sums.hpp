// The inner sum of the vertex-fan fold check (random_pose.cpp), vectorised on its own.
#ifndef MULTICAGE_ANIMATE_FAN_SUMS_HPP
#define MULTICAGE_ANIMATE_FAN_SUMS_HPP

namespace cv {
namespace multicage {

/** sx[i] += rows[q][i] * dx[q], sy[i] += rows[q][i] * dy[q] for q = 0 .. moved - 1 in that
order, i in [0, count): each product rounded, then each sum, never fused, so the bits are those
of the plain loop on any instruction set (poses replayed by seed depend on them). */
void accumulateFanSums(const double* const* rows, const double* dx, const double* dy, int moved,
                       int count, double* sx, double* sy);

}  // namespace multicage
}  // namespace cv

#endif
