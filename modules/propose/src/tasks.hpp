// Work shared out between the cores (private): independent tasks taken in turn by as many
// workers as there are cores, and the face searches that run beside the face-blind
// segmentation.
#ifndef MULTICAGE_PROPOSE_TASKS_HPP
#define MULTICAGE_PROPOSE_TASKS_HPP

#include <functional>
#include <vector>

namespace cv {
namespace multicage {
namespace propose_detail {

using Tasks = std::vector<std::function<void()>>;

/** Runs independent `tasks`, each on one thread (a parallel loop inside one runs serially), on
at most cv::getNumThreads() workers: each worker takes the next task not yet taken, so tasks
given longest first keep the cores busy to the end. A single task runs on the calling thread,
its own parallel loops on every core. Exceptions reach the caller. */
void runTasks(const Tasks& tasks);

/** Work beside the face-blind segmentation that decides whether it is wanted: the proposal's
profile and small face searches (propose.cpp), which a face found makes the segmentation moot.
`tasks` (longest first) may run beside the segmentation's own work; `wanted`, called once they
have all run, says whether the segmentation is still wanted. Empty: nothing beside. */
struct Beside {
    Tasks tasks;
    std::function<bool()> wanted;

    explicit operator bool() const { return !tasks.empty() || wanted; }
    /** The tasks on every core (runTasks), then wanted(); true when empty. */
    bool run() const;
};

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv

#endif
