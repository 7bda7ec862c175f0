// multicage propose IMAGE -o CAGE.yml: automatic multicage proposal.
#include "cli_util.hpp"

namespace multicage_cli {

void addProposeCommand(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand("propose", "Propose a multicage for IMAGE (not available yet)");
    cmd->callback([] { throw Failure("automatic proposal is not available in this build yet"); });
}

}  // namespace multicage_cli
