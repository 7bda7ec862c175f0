// Binding::apply for callers inside the library that use node rows as they are written.
#ifndef MULTICAGE_INTERNAL_APPLY_ROWS_HPP
#define MULTICAGE_INTERNAL_APPLY_ROWS_HPP

#include <functional>
#include <opencv2/multicage/coordinates.hpp>

namespace cv {
namespace multicage {

/** Binding::apply (the same values), calling rowsDone(gy0, gy1), if given, on the thread that has
just written node rows [gy0, gy1) of positions, while they are still in its cache: blocks of whole
rows that together cover the grid once, in no particular order, from several threads at once. For
a check that would otherwise read every node back from memory (the CPU backend's fold check). */
void applyRows(const Binding& binding, InputArray pose, OutputArray positions,
               const std::function<void(int gy0, int gy1)>& rowsDone);

}  // namespace multicage
}  // namespace cv

#endif
