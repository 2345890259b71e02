// Reading a solver answer (the "json" output of the encoding) back into a trajectory.
#pragma once

#include <optional>
#include <string>

#include "planner/model/trajectory.h"

namespace ctb {

// Reads a solver solution (the "json" output of the encoding) into a trajectory cut at g.
// Returns nullopt with a message when the solution lacks a variable or is inconsistent.
std::optional<Trajectory> ExtractTrajectory(const Json& solution, const Domain& d,
                                            const StatePlan& sp, int horizon, std::string& error);

}  // namespace ctb
