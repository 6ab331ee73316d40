#include "rgbd_lane_detector/params_io.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <type_traits>

#include <yaml-cpp/yaml.h>

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

// A value's text: an enum name (param_enums.def), a YAML 1.1 boolean or a finite number.
bool parseValue(const std::string& text, double& v) {
  static const struct {
    const char* name;
    int value;
  } kEnumNames[] = {
#define RLD_ENUM(type, enumerator, name, value, description) {#name, value},
#include "rgbd_lane_detector/param_enums.def"
#undef RLD_ENUM
  };
  for (const auto& e : kEnumNames)
    if (text == e.name) {
      v = e.value;
      return true;
    }
  for (const char* t : {"true", "True", "TRUE"})
    if (text == t) return v = 1.0, true;
  for (const char* f : {"false", "False", "FALSE"})
    if (text == f) return v = 0.0, true;
  char* end = nullptr;
  v = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && std::isfinite(v);
}

std::string where(const std::string& source, const YAML::Mark& mark) {
  return mark.is_null() ? source : source + ":" + std::to_string(mark.line + 1);
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

bool loadParamsYaml(const std::string& path, Params& p, std::string* error,
                    std::vector<std::string>* ignored) {
  std::ifstream in(path);
  if (!in) {
    if (error) *error = "cannot open parameter file " + path;
    return false;
  }
  return parseParamsYaml(in, path, p, error, ignored);
}

bool parseParamsYaml(std::istream& in, const std::string& source, Params& p, std::string* error,
                     std::vector<std::string>* ignored) {
  YAML::Node root;
  try {
    root = YAML::Load(in);
  } catch (const YAML::Exception& e) {
    if (error) *error = source + ": not YAML: " + e.what();
    return false;
  }
  if (root.IsNull()) return true;  // an empty file changes nothing
  if (!root.IsMap()) {
    if (error) *error = source + ": expected a map of parameter names to values";
    return false;
  }
  // the `name: value` pairs in file order, those in nested maps (a node's namespace) included
  std::vector<std::pair<std::string, YAML::Node>> entries;
  std::function<void(const YAML::Node&)> collect = [&](const YAML::Node& map) {
    for (const auto& kv : map) {
      if (kv.second.IsMap())
        collect(kv.second);
      else
        entries.emplace_back(kv.first.IsScalar() ? kv.first.Scalar() : std::string(), kv.second);
    }
  };
  collect(root);
  // a mode key selects the preset the other keys apply to, wherever it is
  Params out = p;
  for (const auto& [key, value] : entries) {
    if (key != "mode") continue;
    if (!(value.IsScalar() && paramsForMode(value.Scalar(), out))) {
      if (error)
        *error = where(source, value.Mark()) + ": unknown mode '" +
                 (value.IsScalar() ? value.Scalar() : std::string("(not a name)")) + "'";
      return false;
    }
  }
  for (const auto& [key, value] : entries) {
    if (key == "mode") continue;
    const Field* f = find(key);
    if (!f) {  // node settings (queue_size, ...), typos
      if (ignored) ignored->push_back(key);
      continue;
    }
    if (value.IsNull()) continue;  // `name:` without a value
    double v = 0;
    if (!value.IsScalar() || !parseValue(trim(value.Scalar()), v)) {
      if (error)
        *error = where(source, value.Mark()) + ": bad value '" +
                 (value.IsScalar() ? value.Scalar() : std::string("(not a scalar)")) + "' for " +
                 key;
      return false;
    }
    f->set(out, v);
  }
  p = out;
  return true;
}

}  // namespace rgbd_lane_detector
