// SPDX-License-Identifier: Zlib
#pragma once
/// @file Expected.hpp
/// Error values for every fallible call: the per-step path never throws, it returns an Expected.

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace hydrotex {

/// A failure: one line, naming the file or the value at fault and what is wrong with it.
struct Error {
  std::string message;  ///< e.g. "ship.obj: vertex 12 has a NaN coordinate"
};

/// Either a value or an Error (std::expected is C++23; this is the small part of it we need).
template <class T>
class [[nodiscard]] Expected {
 public:
  /// Success.
  Expected(T value) : state_(std::in_place_index<0>, std::move(value)) {}
  /// Failure.
  Expected(Error error) : state_(std::in_place_index<1>, std::move(error)) {}

  /// True when a value is held.
  bool ok() const { return state_.index() == 0; }
  /// True when a value is held.
  explicit operator bool() const { return ok(); }

  /// The value; only valid when ok().
  T& value() & { assert(ok()); return std::get<0>(state_); }
  /// The value; only valid when ok().
  const T& value() const& { assert(ok()); return std::get<0>(state_); }
  /// The value, moved out; only valid when ok().
  T&& value() && { assert(ok()); return std::get<0>(std::move(state_)); }
  /// Member access to the value; only valid when ok().
  T* operator->() { return &value(); }
  /// Member access to the value; only valid when ok().
  const T* operator->() const { return &value(); }
  /// The value; only valid when ok().
  T& operator*() & { return value(); }
  /// The value; only valid when ok().
  const T& operator*() const& { return value(); }

  /// The error; only valid when !ok().
  const Error& error() const { assert(!ok()); return std::get<1>(state_); }

 private:
  std::variant<T, Error> state_;
};

/// Success or an Error, for calls that return nothing else.
struct Ok {};
/// Result of a call that returns nothing but may fail.
using Status = Expected<Ok>;

}  // namespace hydrotex
