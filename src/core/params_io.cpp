#include "rgbd_lane_detector/params_io.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <type_traits>

namespace rgbd_lane_detector {
namespace {

struct Field {
  std::function<void(Params&, double)> set;
  std::function<double(const Params&)> get;
};

// An integer field from a double: truncated toward zero, saturated at the int range (a cast of
// an out-of-range or NaN double is undefined behaviour); NaN leaves the field unchanged.
// sanitize() then clamps to the field's own range.
bool toInt(double v, int& out) {
  if (std::isnan(v)) return false;
  if (v >= static_cast<double>(std::numeric_limits<int>::max()))
    out = std::numeric_limits<int>::max();
  else if (v <= static_cast<double>(std::numeric_limits<int>::min()))
    out = std::numeric_limits<int>::min();
  else
    out = static_cast<int>(v);
  return true;
}

// Field of any type: numbers as doubles, booleans as 0/1, enums as their integer value.
template <typename T>
Field field(T Params::*m) {
  return {[m](Params& p, double v) {
            if constexpr (std::is_same_v<T, bool>) {
              p.*m = v != 0.0;
            } else if constexpr (std::is_enum_v<T> || std::is_integral_v<T>) {
              int i = 0;
              if (toInt(v, i)) p.*m = static_cast<T>(i);
            } else {
              p.*m = static_cast<T>(v);
            }
          },
          [m](const Params& p) {
            if constexpr (std::is_enum_v<T>) return static_cast<double>(static_cast<int>(p.*m));
            else return static_cast<double>(p.*m);
          }};
}

const std::vector<std::pair<std::string, Field>>& fields() {
  static const std::vector<std::pair<std::string, Field>> table = {
#define RLD_PARAM(group, type, name, improved, paper, min, max, level, description) \
  {#name, field(&Params::name)},
#include "rgbd_lane_detector/params.def"
#undef RLD_PARAM
  };
  return table;
}

const Field* find(const std::string& name) {
  for (const auto& f : fields())
    if (f.first == name) return &f.second;
  return nullptr;
}

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\"'");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r\"'");
  return s.substr(a, b - a + 1);
}

bool parseValue(const std::string& text, double& v) {
  static const std::map<std::string, double> words = {
      {"true", 1},  {"True", 1},      {"TRUE", 1},     {"false", 0},       {"False", 0},
      {"FALSE", 0}, {"near_high", 0}, {"far_high", 1}, {"three_point", 0}, {"least_squares", 1},
      {"road_surface", 2}};
  const auto w = words.find(text);
  if (w != words.end()) {
    v = w->second;
    return true;
  }
  char* end = nullptr;
  v = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && std::isfinite(v);
}

}  // namespace

const std::vector<std::string>& paramNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& f : fields()) n.push_back(f.first);
    return n;
  }();
  return names;
}

bool setParam(Params& p, const std::string& name, double value) {
  const Field* f = find(name);
  if (!f) return false;
  f->set(p, value);
  return true;
}

bool setParamText(Params& p, const std::string& name, const std::string& text,
                  std::string* error) {
  const Field* f = find(name);
  if (!f) {
    if (error) *error = "unknown parameter '" + name + "'";
    return false;
  }
  double v = 0;
  if (!parseValue(trim(text), v)) {
    if (error) *error = "invalid value '" + text + "' for parameter '" + name + "'";
    return false;
  }
  f->set(p, v);
  return true;
}

bool getParam(const Params& p, const std::string& name, double& value) {
  const Field* f = find(name);
  if (!f) return false;
  value = f->get(p);
  return true;
}

bool loadParamsYaml(const std::string& path, Params& p, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (error) *error = "cannot open parameter file " + path;
    return false;
  }
  return parseParamsYaml(in, path, p, error);
}

bool parseParamsYaml(std::istream& in, const std::string& path, Params& p, std::string* error) {
  // key/value lines; a mode line selects the preset the other keys apply to, wherever it is
  std::vector<std::pair<std::string, std::string>> entries;
  std::vector<int> line_numbers;
  Params out = p;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = trim(line.substr(0, colon));
    const std::string text = trim(line.substr(colon + 1));
    if (key.empty() || text.empty()) continue;
    if (key == "mode") {
      if (!paramsForMode(text, out)) {
        if (error) *error = path + ":" + std::to_string(line_no) + ": unknown mode '" + text + "'";
        return false;
      }
      continue;
    }
    entries.emplace_back(key, text);
    line_numbers.push_back(line_no);
  }
  for (size_t i = 0; i < entries.size(); ++i) {
    const Field* f = find(entries[i].first);
    if (!f) continue;
    double v = 0;
    if (!parseValue(entries[i].second, v)) {
      if (error)
        *error = path + ":" + std::to_string(line_numbers[i]) + ": bad value '" +
                 entries[i].second + "' for " + entries[i].first;
      return false;
    }
    f->set(out, v);
  }
  p = out;
  return true;
}

}  // namespace rgbd_lane_detector
