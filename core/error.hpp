// Errors raised by library code on bad input. Library code never prints or exits: it throws
// InputError with a message naming the file, line and field, and the caller (apps/) reports it.
#pragma once

#include <stdexcept>
#include <string>

namespace statebench {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace statebench
