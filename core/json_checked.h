// JSON as Linkscape reads its files (presets and the descriptions in them):
// the parse refuses what nlohmann::json would accept silently or could not
// take apart safely, and the accessors name the place of a value of the
// wrong type.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace linkscape {

// Limits of a preset file, far above any real one (a shipped preset is at
// most a few KiB and 8 levels deep): checked before it is read further.
inline constexpr std::size_t kMaxPresetBytes = 1 << 20;
inline constexpr int kMaxPresetNesting = 64;  // objects and arrays within each other

// Parses `text`, refusing objects and arrays nested deeper than `max_depth`
// (the recursive code that walks a document would overflow the stack) and an
// object that gives a key twice (which value counts would be a guess). Throws
// std::invalid_argument naming the place as a JSON pointer, or
// nlohmann::json::parse_error for malformed text.
nlohmann::json parse_json_checked(const std::string& text, int max_depth);

// A JSON library error as a user reads it: its message without the library's
// "[json.exception.parse_error.101] " code.
std::string json_error_text(const nlohmann::json::exception& error);

// The value as a string, number or boolean; std::invalid_argument
// "WHERE: must be a string, got 5" otherwise.
std::string string_at(const nlohmann::json& value, const std::string& where);
double number_at(const nlohmann::json& value, const std::string& where);
bool bool_at(const nlohmann::json& value, const std::string& where);

}  // namespace linkscape
