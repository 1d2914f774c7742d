#pragma once
// Temporary files and directories this process has made and not yet committed or removed.
// If SIGINT, SIGTERM or SIGHUP ends the process, its handler removes them (files first, then
// directories) before the process dies of the signal, so an interrupted run or conversion
// leaves no `*.tmp.*` file and no staging directory behind.
#include <string>

namespace texsim {

// Installs the handler for SIGINT, SIGTERM and SIGHUP (once, from main).
void install_temp_cleanup();
// Starts and stops tracking a path (a path already tracked is tracked once). At most 256 paths
// of up to 4095 bytes are tracked at a time; others are not removed on a signal.
void track_temp(const std::string& path);
void untrack_temp(const std::string& path);
// Removes a scratch file and stops tracking it.
void remove_temp(const std::string& path);

}  // namespace texsim
