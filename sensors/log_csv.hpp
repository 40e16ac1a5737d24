// One CSV line of a recorded log per measurement (columns: log_format.hpp, docs/log-format.md).
// Numbers are written in shortest round-trip form (core/csv.hpp), so parsing a written line gives
// back the identical measurement, bit for bit.
#pragma once

#include <string>
#include <string_view>

#include "core/csv.hpp"
#include "core/measurements.hpp"
#include "sensors/log_format.hpp"

namespace statebench::sensors {

// The layout of a file from its header's column names (ParseCsvHeader checked the type's own
// columns): extra columns are allowed only as the complete gnss velocity set. Throws InputError
// naming `file`:1 otherwise.
LogCsvLayout LogCsvLayoutOf(LogStreamType type, const std::vector<std::string>& header,
                            std::string_view file);

// Appends the line (ending in '\n') of a measurement that is not a LidarScan. In a gnss file
// with velocity columns a fix without velocity leaves the six cells empty; a fix with velocity
// in a file without them is a programmer error (LogWriter chooses the layout).
void AppendLogCsvRow(std::string& out, const Measurement& m, const LogCsvLayout& layout);
// Appends the sweep-index line of a lidar scan stored in `pcd_file` (a name in the sensor's
// folder).
void AppendLidarIndexRow(std::string& out, const LidarScan& scan, std::string_view pcd_file);

// Columns of the measurement stamp and the arrival stamp in the type's file.
struct StampColumns {
  std::size_t stamp = 0;
  std::size_t arrival = 1;
};
StampColumns StampColumnsOf(LogStreamType type);

// Parses a data row of `type` (not lidar) for sensor `id`. Throws InputError naming the file,
// line and column on a missing or extra value, a non-number, a non-finite number or an unknown
// status.
// In a gnss file with velocity columns the six cells are all numbers (sigmas > 0) or all empty
// (no velocity at that fix).
Measurement ParseLogCsvRow(const LogCsvLayout& layout, const std::string& id, const CsvRow& row);

// Checks the row has exactly the layout's columns (throws otherwise).
void CheckColumnCount(const LogCsvLayout& layout, const CsvRow& row);

}  // namespace statebench::sensors
