#pragma once
/// @file format.hpp  Numbers as text, one definition each for the writers, reports and messages.

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>

namespace hemicontact {

/// printf's %g with @p prec significant digits: tables, logs and messages.
inline std::string fmt(double v, int prec = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

/// Appends the shortest text that reads back to the same double (exact and diff-friendly; "inf"
/// for g = +∞): the CSV and VTU writers.
inline void append_round_trip(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

/// The shortest text that reads back to the same double ("inf", "nan" too): messages that quote a
/// value the user gave, which %g would round (nu = 0.9999999999 shown as "1").
inline std::string round_trip(double v) {
  std::string s;
  append_round_trip(s, v);
  return s;
}

/// The shortest round-trip text of @p v, or "" when it is not finite (a CSV cell with no value).
inline std::string csv_number(double v) {
  if (!std::isfinite(v)) return "";
  std::string s;
  append_round_trip(s, v);
  return s;
}

}  // namespace hemicontact
