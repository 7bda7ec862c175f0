// The one way the library picks a CPU kernel set (internal): every kernel written or compiled for
// AVX2 or AVX-512 is chosen by cpuLevel(), so the environment cap MULTICAGE_CPU reaches all of
// them and a machine with AVX-512 can run and check what a CPU without it would
// (docs/cpu-kernels.md).
//
// Two kinds of kernels use it. Hand-written ones (the raster's, the pull's, the sampler's) are
// functions compiled for a level (MULTICAGE_TARGET_X86_64_V3 / _V4) and picked at run time.
// Loops left to the compiler to vectorise are written once, as an always-inline body, and
// MULTICAGE_CPU_CLONES compiles that body for each level and picks one per call.
#ifndef MULTICAGE_INTERNAL_CPU_DISPATCH_HPP
#define MULTICAGE_INTERNAL_CPU_DISPATCH_HPP

#include <cstdlib>
#include <cstring>

namespace cv {
namespace multicage {

/** The kernel sets: the x86-64 baseline (SSE2), x86-64-v3 (AVX2, FMA, BMI1/2, LZCNT, MOVBE,
F16C) and x86-64-v4 (x86-64-v3 and AVX-512 F, BW, CD, DQ, VL). */
enum class CpuLevel { baseline = 1, x86_64_v3 = 3, x86_64_v4 = 4 };

/** The highest level the environment allows: MULTICAGE_CPU=baseline, avx2 (x86-64-v3) or
avx512 / unset (whatever the CPU runs); any other value is ignored. Read once. */
inline CpuLevel cpuLevelCap() {
    static const CpuLevel cap = [] {
        const char* v = std::getenv("MULTICAGE_CPU");
        if (!v) return CpuLevel::x86_64_v4;
        if (std::strcmp(v, "baseline") == 0) return CpuLevel::baseline;
        if (std::strcmp(v, "avx2") == 0) return CpuLevel::x86_64_v3;
        return CpuLevel::x86_64_v4;
    }();
    return cap;
}

/** The level this CPU runs, under the cap. GCC 12 asks for a level at once (a virtual machine
may hide any one feature); elsewhere the features that matter are asked one by one. */
inline CpuLevel cpuLevel() {
    static const CpuLevel level = [] {
#if defined(__x86_64__) && defined(__GNUC__)
#if !defined(__clang__) && __GNUC__ >= 12
        const bool v3 = __builtin_cpu_supports("x86-64-v3");
        const bool v4 = v3 && __builtin_cpu_supports("x86-64-v4");
#else
        const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                        __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
                        __builtin_cpu_supports("popcnt");
        const bool v4 = v3 && __builtin_cpu_supports("avx512f") &&
                        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512cd") &&
                        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
#endif
        const CpuLevel cpu = v4   ? CpuLevel::x86_64_v4
                             : v3 ? CpuLevel::x86_64_v3
                                  : CpuLevel::baseline;
        return static_cast<int>(cpu) < static_cast<int>(cpuLevelCap()) ? cpu : cpuLevelCap();
#else
        return CpuLevel::baseline;
#endif
    }();
    return level;
}

/** Whether x86-64-v3 (AVX2) code may run here, under the cap. */
inline bool cpuHasX86_64_v3() {
    return static_cast<int>(cpuLevel()) >= static_cast<int>(CpuLevel::x86_64_v3);
}
/** Whether x86-64-v4 (AVX-512) code may run here, under the cap. */
inline bool cpuHasX86_64_v4() {
    return cpuLevel() == CpuLevel::x86_64_v4;
}

}  // namespace multicage
}  // namespace cv

#if defined(__x86_64__) && defined(__GNUC__)
/** A function compiled for x86-64-v3 or x86-64-v4: call it only where cpuLevel() allows. */
#define MULTICAGE_TARGET_X86_64_V3 __attribute__((target("arch=x86-64-v3")))
#define MULTICAGE_TARGET_X86_64_V4 __attribute__((target("arch=x86-64-v4")))
#endif

// GCC only: clang contracts a * b + c into fused multiply-adds by default, so its x86-64-v3 copy
// would round otherwise than its baseline one (the copies must give the same bits).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define MULTICAGE_HAVE_CPU_CLONES 1
#endif

/** MULTICAGE_CPU_CLONES(RET, NAME, PARAMS, ARGS): defines `RET NAME PARAMS`, which calls
`NAME##Kernel ARGS` compiled for the CPU's level: the body, written once as a
MULTICAGE_ALWAYS_INLINE function, is inlined into a copy per level. Where there are no levels
(clang, other CPUs) NAME calls the body as it is. */
#define MULTICAGE_ALWAYS_INLINE inline __attribute__((always_inline))
#if defined(MULTICAGE_HAVE_CPU_CLONES)
#define MULTICAGE_CPU_CLONES(ret, name, params, args)              \
    MULTICAGE_TARGET_X86_64_V4 static ret name##X86_64_v4 params { \
        return name##Kernel args;                                  \
    }                                                              \
    MULTICAGE_TARGET_X86_64_V3 static ret name##X86_64_v3 params { \
        return name##Kernel args;                                  \
    }                                                              \
    static ret name##Baseline params {                             \
        return name##Kernel args;                                  \
    }                                                              \
    ret name params {                                              \
        switch (::cv::multicage::cpuLevel()) {                     \
            case ::cv::multicage::CpuLevel::x86_64_v4:             \
                return name##X86_64_v4 args;                       \
            case ::cv::multicage::CpuLevel::x86_64_v3:             \
                return name##X86_64_v3 args;                       \
            default:                                               \
                return name##Baseline args;                        \
        }                                                          \
    }
#else
#define MULTICAGE_CPU_CLONES(ret, name, params, args) \
    ret name params {                                 \
        return name##Kernel args;                     \
    }
#endif

#endif
