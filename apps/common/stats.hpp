// Statistics the tools print (header-only: the editor uses it without the fixtures).
#ifndef MULTICAGE_APPS_STATS_HPP
#define MULTICAGE_APPS_STATS_HPP

#include <algorithm>
#include <vector>

namespace multicage_apps {

/** Median of samples (copied and sorted; the mean of the middle two for an even count), 0 for
none. */
inline double median(std::vector<double> samples) {
    if (samples.empty()) return 0.0;
    std::sort(samples.begin(), samples.end());
    const size_t n = samples.size();
    return n % 2 ? samples[n / 2] : 0.5 * (samples[n / 2 - 1] + samples[n / 2]);
}

}  // namespace multicage_apps

#endif
