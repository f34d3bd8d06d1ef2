#pragma once
// Exception types thrown by scanmesh libraries. The libraries never print or exit;
// command-line programs catch these and map them to exit codes (InputError -> 1, UsageError -> 2).
#include <stdexcept>
#include <string>

namespace scanmesh {

/// Base class of every error scanmesh throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The input (a file, a mesh, a cloud) is missing, malformed or unusable.
/// The message names the file (when there is one) and what is wrong with it.
class InputError : public Error {
 public:
  using Error::Error;
};

/// A parameter or a combination of parameters is invalid.
class UsageError : public Error {
 public:
  using Error::Error;
};

/// Writing an output failed (permissions, disk full, ...).
class OutputError : public Error {
 public:
  using Error::Error;
};

}  // namespace scanmesh
