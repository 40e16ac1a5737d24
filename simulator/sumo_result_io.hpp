// SumoResult to and from a binary file (the stage cache's SUMO entry): every field, every bit.
#pragma once

#include <filesystem>

#include "simulator/sumo_result.hpp"

namespace statebench::sim {

// Throws InputError when the file cannot be written.
void WriteSumoResult(const SumoResult& result, const std::filesystem::path& file);
// Throws InputError when the file cannot be read or is not a SumoResult of this format.
SumoResult ReadSumoResult(const std::filesystem::path& file);

}  // namespace statebench::sim
