#pragma once
/// @file text.hpp  Text from outside (scene values, keys, file names): UTF-8 validation and a
/// printable form for messages.
///
/// Every result file is JSON, and JSON text is UTF-8: a string that is not valid UTF-8 cannot be
/// written at all (nlohmann::json::dump throws). Such text is therefore refused where it enters
/// (a --set description with a Latin-1 byte once lost a whole study's results at the end).

#include <cstddef>
#include <string>

namespace hemicontact {

/// @return the offset of the first byte of @p text that does not start (or continue) a valid
/// UTF-8 sequence, or std::string::npos when @p text is valid UTF-8. Strict, as JSON's writers
/// are: no overlong forms, no surrogates (U+D800..U+DFFF), nothing above U+10FFFF.
std::size_t invalid_utf8_at(const std::string& text);

/// @return "byte 0xE9 at position 3": what is wrong with @p text (invalid_utf8_at(text) != npos).
std::string describe_invalid_utf8(const std::string& text);

/// @return @p text for a one-line message: bytes that are not valid UTF-8 and control characters
/// (NUL, newline, escape, ...) as \xNN, so that a message neither stops at a NUL nor breaks its
/// line; valid UTF-8 (Γ3, ν) is kept. The result is valid UTF-8 with no control character.
std::string printable(const std::string& text);

}  // namespace hemicontact
