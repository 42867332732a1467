// SPDX-License-Identifier: Zlib
// `hydrotex stability MESH (--mass KG | --density KG_M3 | --displacement M3) ... [--axis roll|pitch]
//   [--max-deg 180] [--step-deg 2] [--csv OUT] [--plot OUT.png] [--json]`: the righting-lever (GZ)
// curve at constant displacement with free sinkage and free trim (or heel), and what it tells.

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "FloatingOptions.hpp"
#include "ToolSupport.hpp"
#include "Verbs.hpp"

namespace hydrotex::tool {

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;

struct StabilityOptions {
  FloatingOptions body;
  std::string axis = "roll";
  double maxDegrees = 180.0;
  double stepDegrees = 2.0;
  std::string csvPath;
  std::string plotPath;
  bool json = false;
};

nlohmann::json optionalDegrees(const std::optional<double>& angle) {
  return angle ? nlohmann::json(*angle / kDeg) : nlohmann::json(nullptr);
}
nlohmann::json optionalNumber(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

/// A path as a gnuplot single-quoted string ('' stands for a quote there).
std::string gnuplotQuoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

/// Plots the curve, GM's tangent (reaching GM at 1 rad) and the marked angles into `pngPath` with
/// gnuplot, from data and a script in a scratch folder removed afterwards.
Status plotCurve(const RightingLeverCurve& curve, const std::string& axis, const std::string& pngPath) {
  namespace fs = std::filesystem;
  std::error_code ignored;
  const fs::path dir = fs::temp_directory_path(ignored) / ("hydrotex_stability_" + std::to_string(::getpid()));
  fs::create_directories(dir, ignored);
  {
    std::ofstream dat(dir / "curve.dat");
    for (std::size_t k = 0; k < curve.angles.size(); ++k) dat << curve.angles[k] / kDeg << ' ' << curve.levers[k] << '\n';
    std::ofstream marks(dir / "marks.dat");
    marks.precision(4);
    marks << curve.angleOfMaxLever / kDeg << ' ' << curve.maxLever << " \"max GZ " << curve.maxLever << " m at "
          << curve.angleOfMaxLever / kDeg << " deg\"\n";
    if (curve.angleOfVanishingStability)
      marks << *curve.angleOfVanishingStability / kDeg << " 0 \"vanishing at " << *curve.angleOfVanishingStability / kDeg
            << " deg\"\n";
    const double radian = 1.0 / kDeg;
    std::ofstream gp(dir / "plot.gp");
    gp.precision(6);
    gp << "set terminal pngcairo size 900,600\nset output " << gnuplotQuoted(fs::absolute(pngPath).string()) << "\n"
       << "set grid\nset key below\nset xzeroaxis lt -1\nset offsets 0, 0, graph 0.12, graph 0.05\n"
       << "set title 'Righting lever (" << axis << ", free sinkage and " << (axis == "roll" ? "trim" : "heel")
       << "), GM = " << curve.gm << " m'\n"
       << "set xlabel '" << (axis == "roll" ? "heel" : "trim") << " (deg)'\nset ylabel 'GZ (m)'\n"
       << "set arrow from " << radian << ",0 to " << radian << "," << curve.gm << " nohead dt 3\n"
       << "set label 'GM at 57.3 deg' at " << radian << "," << curve.gm << " offset 1,0\n"
       << "plot 'curve.dat' using 1:2 with linespoints pt 7 ps 0.5 title 'GZ', "
       << "[0:" << radian << "] " << curve.gm << " * x * pi / 180 with lines dt 2 title 'GM tangent', "
       << "'marks.dat' using 1:2 with points pt 6 ps 2 notitle, '' using 1:2:3 with labels offset 0,1.5 notitle\n";
  }
  const std::string command = "cd '" + dir.string() + "' && gnuplot plot.gp >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  fs::remove_all(dir, ignored);
  if (status != 0) return Error{"--plot " + pngPath + ": gnuplot failed (can the file be written?)"};
  return Ok{};
}

int runStability(const StabilityOptions& options) {
  if (!(options.stepDegrees > 0.0)) {
    std::ostringstream message;
    message << "--step-deg " << options.stepDegrees << ": must be positive";
    return reportError(Error{message.str()});
  }
  if (!options.plotPath.empty() && std::system("command -v gnuplot >/dev/null 2>&1") != 0)
    return reportError(Error{"--plot " + options.plotPath + ": needs gnuplot on the PATH"});
  Expected<std::unique_ptr<FloatingSetup>> setup = loadFloatingBody(options.body);
  if (!setup) return reportError(setup.error());
  FloatingSetup& s = **setup;
  StabilityCurveSettings settings;
  settings.floating = s.settings;
  settings.axis = options.axis == "roll" ? StabilityAxis::Roll : StabilityAxis::Pitch;
  settings.maxAngle = options.maxDegrees * kDeg;
  settings.step = options.stepDegrees * kDeg;
  Expected<RightingLeverCurve> curve = rightingLeverCurve(s.mesh, s.body, settings, s.answer);
  if (!curve) return reportError(curve.error());

  if (!options.csvPath.empty()) {
    std::ofstream csv(options.csvPath);
    csv.precision(12);
    csv << "angle_deg,gz_m," << (options.axis == "roll" ? "trim_deg" : "heel_deg") << "\n";
    for (std::size_t k = 0; k < curve->angles.size(); ++k)
      csv << curve->angles[k] / kDeg << ',' << curve->levers[k] << ',' << curve->otherAngles[k] / kDeg << '\n';
    if (!csv) return reportError(Error{"--csv " + options.csvPath + ": cannot be written"});
  }
  if (!options.plotPath.empty())
    if (Status plotted = plotCurve(*curve, options.axis, options.plotPath); !plotted) return reportError(plotted.error());

  nlohmann::json out;
  out["axis"] = options.axis;
  nlohmann::json points = nlohmann::json::array();
  for (std::size_t k = 0; k < curve->angles.size(); ++k) points.push_back({curve->angles[k] / kDeg, curve->levers[k]});
  out["curve"] = points;
  out["gm"] = curve->gm;
  out["angle_of_max_gz_deg"] = curve->angleOfMaxLever / kDeg;
  out["max_gz"] = curve->maxLever;
  out["angle_of_vanishing_stability_deg"] = optionalDegrees(curve->angleOfVanishingStability);
  out["area_30_m_rad"] = optionalNumber(curve->area30);
  out["area_40_m_rad"] = optionalNumber(curve->area40);
  addFloatingJson(out, s);

  auto orNone = [](const std::optional<double>& v, double scale, const char* unit) {
    std::ostringstream o;
    o.precision(8);
    if (v) o << *v * scale << unit; else o << "not within the sweep";
    return o.str();
  };
  std::ostringstream text;
  text.precision(8);
  text << s.method.describe(options.body.meshPath) << ", " << options.axis << " righting lever, mass " << s.body.mass
       << " kg in " << s.settings.fluidDensity << " kg/m^3\n"
       << "  GM (slope at 0)           " << curve->gm << " m\n"
       << "  max GZ                    " << curve->maxLever << " m at " << curve->angleOfMaxLever / kDeg << " deg\n"
       << "  vanishing stability       " << orNone(curve->angleOfVanishingStability, 1.0 / kDeg, " deg") << "\n"
       << "  area to 30 deg            " << orNone(curve->area30, 1.0, " m rad") << "\n"
       << "  area to 40 deg            " << orNone(curve->area40, 1.0, " m rad") << "\n"
       << "  angle (deg)   GZ (m)\n";
  for (std::size_t k = 0; k < curve->angles.size(); ++k) {
    char line[64];
    std::snprintf(line, sizeof line, "  %10.3f   %.8g\n", curve->angles[k] / kDeg, curve->levers[k]);
    text << line;
  }
  printResult(options.json, out, text.str());
  return 0;
}
}  // namespace

void addStabilityVerb(CLI::App& app, VerbAction& action) {
  auto options = std::make_shared<StabilityOptions>();
  CLI::App* verb = addVerb(app, action, "stability",
                           "righting-lever (GZ) curve at constant displacement, free sinkage and trim", options,
                           &runStability);
  addFloatingOptions(*verb, options->body);
  verb->add_option("--axis", options->axis, "roll (heel about x, default) or pitch (trim about z)")
      ->check(CLI::IsMember({"roll", "pitch"}));
  verb->add_option("--max-deg", options->maxDegrees, "last angle (degrees, default 180)")->check(CLI::Range(0.0, 180.0));
  verb->add_option("--step-deg", options->stepDegrees, "between samples (degrees, default 2)");
  verb->add_option("--csv", options->csvPath, "write angle_deg,gz_m,<free angle>_deg rows to this file");
  verb->add_option("--plot", options->plotPath, "draw the curve into this PNG (needs gnuplot)");
}

}  // namespace hydrotex::tool
