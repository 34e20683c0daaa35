// undex conform: the protocol conformance check of a structure solver (coupler/conform.cpp).
#pragma once
#include <string>
#include <vector>

namespace undex::coupling {

// Runs command (with " --couple ENDPOINT" appended) once per check, playing the fluid side; prints one
// line per check and returns the number of failed checks. timeout: seconds to wait for the solver.
int conform(const std::vector<std::string>& command, double timeout);

// s quoted for /bin/sh (single quotes, embedded ones escaped).
std::string shell_quote(const std::string& s);

} // namespace undex::coupling
