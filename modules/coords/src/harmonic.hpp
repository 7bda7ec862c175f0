// Harmonic coordinates on the node grid (DeRose & Meyer 2006), private to the coords module.
#ifndef MULTICAGE_HARMONIC_HPP
#define MULTICAGE_HARMONIC_HPP

#include <cstddef>
#include <opencv2/multicage/coordinates.hpp>

namespace cv {
namespace multicage {

/** A node closer than this (in pixels, along a grid line) to a polygon edge is taken to lie on
it: it becomes a Dirichlet node carrying the edge's hat values. Snapping moves a boundary point
by at most this much, far below what a deformation can show, and keeps the Laplace system away
from the near-zero link lengths that would make it ill-conditioned. */
constexpr double kHarmonicOnEdgeTolerance = 1e-4;

/** A Binding with everything but the coefficients filled in: image size, grid step and size,
coordinate type, rest vertices (user vertices, then the frame corners). Shared by both kinds of
coordinates. */
Binding emptyBinding(const Multicage& multicage, int coordinates, int gridStep);

/** What the harmonic solve did, for benchmarks and documentation. */
struct HarmonicStats {
    int unknowns = 0;           //!< nodes off the boundary (rows of the Laplace system)
    int dirichletNodes = 0;     //!< nodes on a polygon edge or vertex
    int components = 0;         //!< regions of the grid that polygons separate
    int solves = 0;             //!< (component, vertex) right-hand sides solved
    size_t matrixNonZeros = 0;  //!< of the Laplace matrices (lower triangle)
    size_t factorNonZeros = 0;  //!< of their LDL^T factors L
};

/** bind() for coordinates == HARMONIC; the multicage has passed validateGeometry().

Discrete harmonic coordinates (DeRose & Meyer 2006) over the node grid: every polygon edge and
the image frame are Dirichlet boundaries carrying each vertex's piecewise-linear hat function;
every other node satisfies the 5-point Laplace equation, with grid links that cross a polygon
cut at the crossing and shortened to it (a symmetric Shortley-Weller stencil, so the system is
symmetric positive definite and reproduces linear functions exactly). Regions that polygons
separate are separate systems, so each region depends only on the polygons that bound it.

Inputs:
  multicage  a valid multicage
  gridStep   >= 1, the node spacing in pixels
Outputs:
  stats      optional: sizes of the systems that were solved
  progress   optional: see bind(..., progress); cancelling throws between steps
Returns a Binding with coordinates = HARMONIC, minConditioning = 1. */
Binding bindHarmonic(const Multicage& multicage, int gridStep, HarmonicStats* stats = nullptr,
                     const BindProgress& progress = BindProgress());

}  // namespace multicage
}  // namespace cv

#endif
