// The floating-point options of the CPU rasteriser's files (private). Include this first in each
// of them, before any other header: a "#pragma GCC optimize" met after some functions are defined
// gives the later ones other options, and GCC then inlines none of the earlier ones (std::min,
// std::fill_n) into them.
//
// No fused multiply-adds, so that every kernel and clone (baseline, AVX2, AVX-512) gives the same
// bits; and no floating-point traps assumed (nothing here enables them), so that the selects of
// the triangle set-up vectorise.
#ifndef MULTICAGE_RASTER_OPTIONS_HPP
#define MULTICAGE_RASTER_OPTIONS_HPP
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off", "no-trapping-math")
#elif defined(__clang__)
#pragma clang fp contract(off)
#endif
#endif
