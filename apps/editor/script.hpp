// The editor's scripted mode (--script FILE): one command per line, run in the real window.
#ifndef MULTICAGE_EDITOR_SCRIPT_HPP
#define MULTICAGE_EDITOR_SCRIPT_HPP

#include <string>
#include <vector>

namespace multicage_editor {

struct ScriptCommand {
    std::string verb;               //!< "load", "drag", ...
    std::vector<std::string> args;  //!< the words after the verb
    int line = 0;                   //!< 1-based line in the script, for messages
};

/** One line per command: verb, its words and what it does (the --help text and the check). */
struct ScriptVerb {
    const char* verb;
    int minArgs, maxArgs;
    const char* usage;
};
const std::vector<ScriptVerb>& scriptVerbs();

/** Parses a script: blank lines and lines starting with '#' are skipped. Throws
std::runtime_error naming the file and line ("s.txt:4: drag needs 3 arguments: drag I DX DY")
for an unknown verb, a wrong argument count or a number that does not parse. */
std::vector<ScriptCommand> parseScript(const std::string& text, const std::string& name);
/** Reads and parses a script file (throws when it cannot be read). */
std::vector<ScriptCommand> loadScript(const std::string& path);

/** The argument as a number; throws std::runtime_error naming the line when it is not one. */
double numberArg(const ScriptCommand& c, size_t i);

}  // namespace multicage_editor

#endif
