#include "core/json_checked.h"

#include <set>
#include <stdexcept>
#include <vector>

namespace linkscape {

using nlohmann::json;

json parse_json_checked(const std::string& text, int max_depth) {
  // The path to the value being read: per open object its keys so far and
  // the current one, per open array the index of the current element.
  struct Level {
    bool object = false;
    std::set<std::string> keys;
    std::string key;
    std::size_t index = 0;
  };
  std::vector<Level> path;
  auto pointer = [&](std::size_t levels) {
    std::string s;
    for (std::size_t l = 0; l < levels; ++l) {
      s += '/';
      if (!path[l].object) {
        s += std::to_string(path[l].index);
        continue;
      }
      for (const char c : path[l].key) s += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);  // RFC 6901
    }
    return s.empty() ? std::string("/") : s;
  };
  auto value_done = [&] {
    if (!path.empty() && !path.back().object) ++path.back().index;
  };
  const json::parser_callback_t check = [&](int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (int(path.size()) >= max_depth)
          throw std::invalid_argument("JSON nested deeper than " + std::to_string(max_depth) + " levels at " +
                                      pointer(path.size()));
        path.push_back({event == json::parse_event_t::object_start, {}, {}, 0});
        break;
      case json::parse_event_t::key: {
        Level& object = path.back();
        object.key = parsed.get<std::string>();
        if (!object.keys.insert(object.key).second)
          throw std::invalid_argument(pointer(path.size()) + ": the key '" + object.key +
                                      "' is given twice in one object");
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        path.pop_back();
        value_done();
        break;
      case json::parse_event_t::value:
        value_done();
        break;
    }
    return true;
  };
  return json::parse(text, check);
}

std::string json_error_text(const nlohmann::json::exception& error) {
  const std::string text = error.what();
  const std::size_t code_end = text.find("] ");
  return text.rfind("[json.exception.", 0) == 0 && code_end != std::string::npos ? text.substr(code_end + 2) : text;
}

namespace {

[[noreturn]] void wrong_type(const json& value, const std::string& where, const char* expected) {
  throw std::invalid_argument(where + ": must be " + expected + ", got " + value.dump());
}

}  // namespace

std::string string_at(const json& value, const std::string& where) {
  if (!value.is_string()) wrong_type(value, where, "a string");
  return value.get<std::string>();
}

double number_at(const json& value, const std::string& where) {
  if (!value.is_number()) wrong_type(value, where, "a number");
  return value.get<double>();
}

bool bool_at(const json& value, const std::string& where) {
  if (!value.is_boolean()) wrong_type(value, where, "true or false");
  return value.get<bool>();
}

}  // namespace linkscape
