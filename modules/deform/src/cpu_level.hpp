// Whether this CPU runs x86-64-v3 or x86-64-v4 code (private): the dispatch of the deform
// module's AVX2 and AVX-512 kernels (raster_avx2.cpp, raster_avx512.cpp and remap_linear.cpp's
// samplers), which are compiled for those levels. (The pull, mesh_pull.cpp, is compiled for
// the features it names and asks for those, under the same cap.)
#ifndef MULTICAGE_CPU_LEVEL_HPP
#define MULTICAGE_CPU_LEVEL_HPP

#include <cstdlib>
#include <cstring>

namespace cv {
namespace multicage {

/** The highest kernel level the environment allows: MULTICAGE_CPU=baseline (no AVX2 or
AVX-512 kernel), avx2 (AVX2 kernels, none of AVX-512) or avx512 / unset (whatever the CPU
runs). It lets one machine time and check the kernels another CPU would run (an AVX-512
server standing in for a laptop without it); any other value is ignored. Read once. */
inline int cpuLevelCap() {
    static const int cap = [] {
        const char* v = std::getenv("MULTICAGE_CPU");
        if (!v) return 4;
        if (std::strcmp(v, "baseline") == 0) return 1;
        if (std::strcmp(v, "avx2") == 0) return 3;
        return 4;
    }();
    return cap;
}

/** Everything x86-64-v3 code may use: AVX2, FMA, BMI1/2, LZCNT, MOVBE, F16C, POPCNT. GCC 12 asks
for the level at once (a virtual machine may hide any one of them); elsewhere the features that
matter are asked one by one. */
inline bool cpuHasX86_64_v3() {
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
    static const bool yes = cpuLevelCap() >= 3 && __builtin_cpu_supports("x86-64-v3");
#else
    static const bool yes = cpuLevelCap() >= 3 && __builtin_cpu_supports("avx2") &&
                            __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
                            __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("popcnt");
#endif
    return yes;
}

/** Everything x86-64-v4 code may use: x86-64-v3 and AVX-512 F, BW, CD, DQ, VL. */
inline bool cpuHasX86_64_v4() {
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
    static const bool yes = cpuLevelCap() >= 4 && __builtin_cpu_supports("x86-64-v4");
#else
    static const bool yes =
        cpuLevelCap() >= 4 && cpuHasX86_64_v3() && __builtin_cpu_supports("avx512f") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512cd") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
#endif
    return yes;
}

}  // namespace multicage
}  // namespace cv

#endif
