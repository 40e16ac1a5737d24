#include "apps/command_support.hpp"

#include <cstdio>
#include <stdexcept>

#include "core/error.hpp"

namespace statebench::app {

std::filesystem::path SetupFileOf(const CliArgs& args, const sensors::LogReader& reader,
                                  const std::filesystem::path& log_dir) {
  if (const auto s = args.Option("setup")) return *s;
  if (const auto s = reader.setup_file()) return *s;
  throw InputError((log_dir / "log.yaml").string() +
                   ": the log names no sensor setup; pass --setup SETUP.yaml");
}

int ExitCodeForCurrentException(const std::string& command) {
  try {
    throw;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "statebench %s: %s\n", command.c_str(), e.what());
    return 2;
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (...) {
    std::fprintf(stderr, "error: unknown failure\n");
    return 1;
  }
}

}  // namespace statebench::app
