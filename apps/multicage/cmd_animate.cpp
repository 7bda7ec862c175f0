// multicage animate IMAGE CAGE.yml -o OUT: keyframed poses to video.
#include "cli_util.hpp"

namespace multicage_cli {

void addAnimateCommand(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand("animate", "Render the cage file's poses as an animation (not available yet)");
    cmd->callback([] { throw Failure("animation is not available in this build yet"); });
}

}  // namespace multicage_cli
