// Reading JSON files (dataset.json, NeRF transforms) with nlohmann-json, strictly: besides the
// syntax, a key repeated in one object is an error. nlohmann keeps the last value of a repeated
// key, so "rate": 25, "rate": 50 would silently drop one of them.
#pragma once

#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/core/error.h"

namespace tdvo {

// Parses [begin, end) as `Json` (nlohmann::json or nlohmann::ordered_json). Throws Error
// "<name>: invalid JSON: ..." on a syntax error or a number beyond double, and "<name>: key
// "k" appears twice in one object" on a repeated key.
template <class Json, class Iterator>
Json parseJsonText(Iterator begin, Iterator end, const std::string& name) {
  std::vector<std::set<std::string>> keys;  // one set per object being read
  auto noRepeatedKeys = [&](int, typename Json::parse_event_t event, Json& parsed) {
    using Event = typename Json::parse_event_t;
    if (event == Event::object_start) {
      keys.emplace_back();
    } else if (event == Event::object_end) {
      keys.pop_back();
    } else if (event == Event::key && !keys.empty() &&
               !keys.back().insert(parsed.template get<std::string>()).second) {
      throw Error(name + ": key \"" + parsed.template get<std::string>() +
                  "\" appears twice in one object (one of its values would be ignored)");
    }
    return true;
  };
  try {
    return Json::parse(begin, end, noRepeatedKeys);
  } catch (const typename Json::exception& e) {  // parse_error; out_of_range for 1e999
    throw Error(name + ": invalid JSON: " + e.what());
  }
}

}  // namespace tdvo
