// What the libFuzzer targets share: reading the input bytes, reporting a finding, a quiet library.
#ifndef MULTICAGE_FUZZ_COMMON_HPP
#define MULTICAGE_FUZZ_COMMON_HPP

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/logger.hpp>

namespace multicage_fuzz {

/** The fuzzer's input as a stream; past its end every byte reads 0. */
struct Bytes {
    const uint8_t* p;
    size_t n;
    uint8_t next() {
        if (!n) return 0;
        --n;
        return *p++;
    }
    float unit() { return next() / 255.f; }
    /** Four bytes as the bits of a float: NaN, infinities and denormals included. */
    float raw() {
        uint32_t u = 0;
        for (int i = 0; i < 4; ++i) u = (u << 8) | next();
        float f;
        std::memcpy(&f, &u, 4);
        return f;
    }
};

/** A broken contract: abort, so that libFuzzer saves the input. */
[[noreturn]] inline void finding(const char* target, const char* what) {
    std::fprintf(stderr, "%s: %s\n", target, what);
    std::abort();
}

/** One thread and no log lines: every execution the same, and fast. */
inline void quietLibrary() {
    cv::setNumThreads(1);
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
}

}  // namespace multicage_fuzz

#endif
