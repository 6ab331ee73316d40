#include "rgbd_lane_detector_tools/command_line.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace rgbd_lane_detector {
namespace tools {

CommandLine::CommandLine(std::string program, std::string summary)
    : program_(std::move(program)), summary_(std::move(summary)) {}

void CommandLine::add(const std::string& name, const std::string& help, std::string* target) {
  addCustom(name, "TEXT", help, [target](const std::string& v, std::string&) {
    *target = v;
    return true;
  });
}

void CommandLine::add(const std::string& name, const std::string& help, int* target) {
  addCustom(name, "N", help, [target, name](const std::string& v, std::string& error) {
    char* end = nullptr;
    const long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || !end || *end != '\0' || x < -2147483647L || x > 2147483647L) {
      error = "--" + name + " expects an integer, got '" + v + "'";
      return false;
    }
    *target = static_cast<int>(x);
    return true;
  });
}

void CommandLine::add(const std::string& name, const std::string& help, double* target) {
  addCustom(name, "X", help, [target, name](const std::string& v, std::string& error) {
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || !end || *end != '\0' || !std::isfinite(x)) {
      error = "--" + name + " expects a number, got '" + v + "'";
      return false;
    }
    *target = x;
    return true;
  });
}

void CommandLine::add(const std::string& name, const std::string& help,
                      std::vector<std::string>* target) {
  addCustom(name, "TEXT", help + " (repeatable)", [target](const std::string& v, std::string&) {
    target->push_back(v);
    return true;
  });
}

void CommandLine::addFlag(const std::string& name, const std::string& help, bool* target) {
  Option o;
  o.name = name;
  o.help = help;
  o.takes_value = false;
  o.set = [target](const std::string&, std::string&) {
    *target = true;
    return true;
  };
  options_.push_back(o);
}

void CommandLine::addCustom(const std::string& name, const std::string& metavar,
                            const std::string& help,
                            std::function<bool(const std::string&, std::string&)> set) {
  Option o;
  o.name = name;
  o.metavar = metavar;
  o.help = help;
  o.set = std::move(set);
  options_.push_back(o);
}

CommandLine::Parse CommandLine::parse(int argc, char** argv, std::vector<std::string>* positional) {
  auto fail = [this](const std::string& m) {
    std::cerr << program_ << ": " << m << "\n(see " << program_ << " --help)\n";
    return Parse::kError;
  };
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::cout << usage();
      return Parse::kHelp;
    }
    if (arg.size() < 3 || arg.compare(0, 2, "--") != 0) {
      if (!positional) return fail("unexpected argument '" + arg + "'");
      positional->push_back(arg);
      continue;
    }
    std::string name = arg.substr(2), value;
    bool has_value = false;
    const size_t eq = name.find('=');
    if (eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      has_value = true;
    }
    const Option* opt = nullptr;
    for (const auto& o : options_)
      if (o.name == name) opt = &o;
    if (!opt) return fail("unknown option --" + name);
    if (opt->takes_value && !has_value) {
      if (i + 1 >= argc) return fail("--" + name + " needs a value");
      value = argv[++i];
    } else if (!opt->takes_value && has_value) {
      return fail("--" + name + " takes no value");
    }
    std::string error;
    if (!opt->set(value, error)) return fail(error.empty() ? "bad value for --" + name : error);
  }
  return Parse::kOk;
}

std::string CommandLine::usage() const {
  std::string u = "usage: " + program_ + " [options]\n" + summary_ + "\n\noptions:\n";
  for (const auto& o : options_) {
    std::string left = "  --" + o.name + (o.takes_value ? " " + o.metavar : "");
    if (left.size() < 30)
      left.resize(30, ' ');
    else
      left += "\n" + std::string(30, ' ');
    u += left + o.help + "\n";
  }
  u += "  -h, --help                  this text\n";
  return u;
}

}  // namespace tools
}  // namespace rgbd_lane_detector
