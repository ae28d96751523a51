// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Error.hpp
/// Exceptions thrown by the core. The library never aborts: failed checks throw these.
#pragma once
#include <stdexcept>
#include <string>

namespace paramesh {

/// Base class of every error the library throws; what() is a one-line, user-readable reason.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
/// A parameter is out of range or inconsistent (names the parameter).
class ParameterError : public Error {
 public:
  using Error::Error;
};
/// The input model cannot be read or is empty.
class InputError : public Error {
 public:
  using Error::Error;
};
/// The user cancelled the run through the progress callback.
class Cancelled : public Error {
 public:
  Cancelled() : Error("meshing cancelled by the user") {}
};
/// An internal invariant does not hold (a bug): thrown instead of assert/abort.
class InternalError : public Error {
 public:
  using Error::Error;
};

}  // namespace paramesh

/// Throws paramesh::InternalError when cond is false (active in release builds too).
#define PM_CHECK(cond, msg)                                                                  \
  do {                                                                                       \
    if (!(cond))                                                                             \
      throw ::paramesh::InternalError(std::string("internal check failed: ") + (msg) + " (" + \
                                      __FILE__ + ":" + std::to_string(__LINE__) + ")");      \
  } while (0)
