#include "tasks.hpp"

#include <algorithm>
#include <atomic>
#include <opencv2/core/utility.hpp>

namespace cv {
namespace multicage {
namespace propose_detail {

void runTasks(const Tasks& tasks) {
    if (tasks.empty()) return;
    if (tasks.size() == 1) {  // on this thread, where its own parallel loops may use every core
        tasks[0]();
        return;
    }
    // A queue rather than a parallel loop over the tasks: the loop would deal them out in
    // blocks, and two long ones could share a core while the other idles.
    std::atomic<size_t> next{0};
    const int workers =
        static_cast<int>(std::min<size_t>(std::max(1, getNumThreads()), tasks.size()));
    parallel_for_(Range(0, workers), [&](const Range& r) {
        for (int w = r.start; w < r.end; ++w)
            for (size_t t = next++; t < tasks.size(); t = next++) tasks[t]();
    });
}

bool Beside::run() const {
    runTasks(tasks);
    return !wanted || wanted();
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv
