// multicage: the command-line tool. Each subcommand lives in its own cmd_*.cpp.
#include <iostream>

#include "cli_util.hpp"

int main(int argc, char** argv) {
    CLI::App app{
        "multicage: multicage image deformation. Bind an image to several nested polygons "
        "once, then deform it for any pose; inner polygons keep what they enclose intact.\n"
        "Start with `multicage demo`, then `multicage propose IMAGE -o cage.yml` and "
        "`multicage deform IMAGE cage.yml -o out.png`.",
        "multicage"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "multicage " MULTICAGE_VERSION);
    app.set_help_all_flag("--help-all", "Print the help of every command");
    multicage_cli::addDemoCommand(app);
    multicage_cli::addDeformCommand(app);
    multicage_cli::addProposeCommand(app);
    multicage_cli::addResizeCommand(app);
    multicage_cli::addPoseCommand(app);
    multicage_cli::addAnimateCommand(app);
    multicage_cli::addBenchCommand(app);
    // "multicage deform: ..." names the subcommand that failed.
    auto fail = [&app](const std::string& message, int code) {
        std::string command = "multicage";
        for (const CLI::App* sub : app.get_subcommands()) command += " " + sub->get_name();
        std::cerr << command << ": " << message
                  << (code == 2 ? " (see " + command + " --help)" : std::string()) << std::endl;
        return code;
    };
    bool known = argc < 2 || argv[1][0] == '-';  // --help, --version
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        known = known || sub->get_name() == argv[1];
    if (!known) {
        std::cerr << "multicage: unknown command '" << argv[1]
                  << "' (demo, propose, resize, deform, pose, animate, bench; see multicage --help)"
                  << std::endl;
        return 2;
    }
    try {
        app.parse(argc, argv);
        return 0;
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return fail(e.what(), 2);
    } catch (const multicage_cli::UsageError& e) {
        return fail(e.what(), 2);
    } catch (const cv::Exception& e) {
        return fail(multicage_cli::reasonOf(e), 1);
    } catch (const std::exception& e) {
        return fail(e.what(), 1);
    }
}
