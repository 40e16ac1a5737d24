// Pieces every statebench subcommand shares.
#pragma once

#include <filesystem>
#include <string>

#include "apps/cli_args.hpp"
#include "sensors/log_reader.hpp"

namespace statebench::app {

// The sensor setup to use with a log: --setup when given, else the log's own; throws InputError
// when neither exists.
std::filesystem::path SetupFileOf(const CliArgs& args, const sensors::LogReader& reader,
                                  const std::filesystem::path& log_dir);

// Exit code of `estimate` and `run` when an estimator produced no estimate (never initialised):
// everything was written, and stderr names what each such estimator was waiting for.
inline constexpr int kExitNoEstimate = 3;

// Call inside `catch (...)`: prints the error as the user should see it and returns the exit
// code: 2 for bad usage (std::invalid_argument) or bad input (InputError), 1 for anything else.
int ExitCodeForCurrentException(const std::string& command);

}  // namespace statebench::app
