/**
 * @file command_line.h
 * @brief Small "--name value" command-line parser shared by the offline tools.
 */
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace rgbd_lane_detector {
namespace tools {

/**
 * @brief Options bound to variables; "--name value", "--name=value" and "--flag" forms.
 * Unknown options and bad values are errors with a message naming the option.
 */
class CommandLine {
 public:
  /// Outcome of parse().
  enum class Parse { kOk, kHelp, kError };

  CommandLine(std::string program, std::string summary);

  void add(const std::string& name, const std::string& help, std::string* target);
  void add(const std::string& name, const std::string& help, int* target);
  void add(const std::string& name, const std::string& help, double* target);
  /// Repeatable option: every occurrence is appended.
  void add(const std::string& name, const std::string& help, std::vector<std::string>* target);
  /// Flag without a value: sets *target to true.
  void addFlag(const std::string& name, const std::string& help, bool* target);
  /// Option with a custom setter returning false (with a message in @p error) on bad values.
  void addCustom(const std::string& name, const std::string& metavar, const std::string& help,
                 std::function<bool(const std::string& value, std::string& error)> set);

  /**
   * @brief Parse arguments; positional arguments go to @p positional (error when null).
   * @return kHelp after printing usage for -h/--help, kError after printing the error.
   */
  Parse parse(int argc, char** argv, std::vector<std::string>* positional = nullptr);
  /// Usage text.
  std::string usage() const;

 private:
  struct Option {
    std::string name, metavar, help;
    bool takes_value = true;
    std::function<bool(const std::string&, std::string&)> set;
  };
  std::string program_, summary_;
  std::vector<Option> options_;
};

}  // namespace tools
}  // namespace rgbd_lane_detector
