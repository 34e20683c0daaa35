// Signals that end a run: SIGINT and SIGTERM end a solver's run at the next step, with its last good state
// written.
#pragma once

namespace undex {

// The solvers' main functions install this; their run loops ask stop_requested().
void install_stop_handler();
bool stop_requested();

} // namespace undex
