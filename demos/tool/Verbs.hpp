// SPDX-License-Identifier: Zlib
#pragma once
// The verbs of the `hydrotex` tool. Each registers itself on the CLI11 app and sets the action to
// run when it is chosen; the action returns the process exit code.

#include <CLI/CLI.hpp>
#include <functional>

namespace hydrotex::tool {

/// What main() runs once the command line is parsed: returns the exit code.
using VerbAction = std::function<int()>;

/// `hydrotex inspect MESH [--json]`: counts, watertightness, UVs, area, volume, bounds.
void addInspectVerb(CLI::App& app, VerbAction& action);
/// `hydrotex mass MESH ...`: mass, volume, centre of mass and inertia, exact or texture.
void addMassVerb(CLI::App& app, VerbAction& action);
/// `hydrotex bake MESH --resolution N --out DIR`: PT, VAT and coverage as images and float data.
void addBakeVerb(CLI::App& app, VerbAction& action);
/// `hydrotex hydrostatics MESH ...`: submerged volume, buoyancy, waterplane, stiffness at a pose.
void addHydrostaticsVerb(CLI::App& app, VerbAction& action);
/// `hydrotex equilibrium MESH ...`: where a free body floats, its draft, heel, trim and GM.
void addEquilibriumVerb(CLI::App& app, VerbAction& action);
/// `hydrotex stability MESH ...`: the righting-lever (GZ) curve and its angles and areas.
void addStabilityVerb(CLI::App& app, VerbAction& action);
/// `hydrotex advise MESH --error E [--json]`: the cheapest method and resolution under an error.
void addAdviseVerb(CLI::App& app, VerbAction& action);
/// `hydrotex simulate SCENE.json [--csv OUT.csv] [--every N] [--json]`: runs a scene in Bullet.
void addSimulateVerb(CLI::App& app, VerbAction& action);

}  // namespace hydrotex::tool
