// SPDX-License-Identifier: Zlib
// hydrotex: command-line tool for the library (inspect meshes, mass properties, bakes, hydrostatics).
// Exit codes: 0 success, 1 a problem with the input (one line on stderr naming the file or value),
// 2 a malformed command line.

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "Verbs.hpp"
#include "hydrotex/Version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"hydrotex: hydrostatics and mass properties of meshes, computed in texture space"};
  app.set_version_flag("--version", hydrotex::versionString());
  app.require_subcommand(1);
  hydrotex::tool::VerbAction action;
  hydrotex::tool::addInspectVerb(app, action);
  hydrotex::tool::addMassVerb(app, action);
  hydrotex::tool::addBakeVerb(app, action);
  hydrotex::tool::addHydrostaticsVerb(app, action);
  hydrotex::tool::addEquilibriumVerb(app, action);
  hydrotex::tool::addStabilityVerb(app, action);
#ifdef HYDROTEX_WITH_ADVISE
  hydrotex::tool::addAdviseVerb(app, action);
#endif
#ifdef HYDROTEX_WITH_BULLET
  hydrotex::tool::addSimulateVerb(app, action);
#endif
  // CLI11 reports an unknown verb as "a subcommand is required"; name it instead.
  std::string verbs;
  bool knownVerb = false;
  for (const CLI::App* verb : app.get_subcommands({})) {
    verbs += (verbs.empty() ? "" : ", ") + verb->get_name();
    knownVerb = knownVerb || (argc > 1 && verb->get_name() == argv[1]);
  }
  if (argc > 1 && argv[1][0] != '-' && !knownVerb) {
    std::cerr << "hydrotex: unknown verb '" << argv[1] << "' (verbs: " << verbs << ")\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, as for every other error; CLI11's own exit() adds a second line.
    std::cerr << "hydrotex: " << e.what() << " (see hydrotex --help)\n";
    return 2;
  }
  try {
    return action ? action() : 2;
  } catch (const std::exception& e) {
    // Nothing below is expected to throw; if a library does (std::bad_alloc on an absurd input),
    // say so on one line instead of aborting.
    std::cerr << "hydrotex: " << e.what() << "\n";
    return 1;
  }
}
