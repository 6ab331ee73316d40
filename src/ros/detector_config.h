/**
 * @file detector_config.h
 * @brief The detector's parameters in the nodelet: the `mode` preset for the parameters not
 * given on the server (start-up) and dynamic_reconfigure's Config to sanitised core Params
 * (every change). Private to the nodelet library.
 */
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <boost/thread/recursive_mutex.hpp>
#include <dynamic_reconfigure/server.h>

#include <ros/node_handle.h>

#include <rgbd_lane_detector/LaneDetectorConfig.h>

#include "rgbd_lane_detector/params.h"

namespace rgbd_lane_detector {

/// What applyModePreset() did, for the nodelet's log line.
struct ModePreset {
  std::string mode;        ///< the preset applied (improved when the requested one is unknown)
  bool known = true;       ///< false: the requested mode was unknown
  std::string overridden;  ///< " name" per given parameter that differs between the presets
  std::string converted;   ///< " name" per parameter given as text (an enum's name) and converted
  std::string invalid;     ///< " name='text'" per parameter whose text is no value of it
  /// The log line ("Mode 'improved': preset values for the parameters not given...").
  std::string text() const {
    return "Mode '" + mode + "': preset values for the parameters not given" +
           (overridden.empty() ? "" : "; given explicitly, overriding the preset:" + overridden) +
           (converted.empty() ? "" : "; given by name:" + converted);
  }
};

/**
 * @brief Write @p mode's preset value of every detector parameter not on the server into
 * @p pnh's namespace (the dynamic_reconfigure server reads them from there); explicit
 * private parameters win (as loadParamsYaml: preset, then keys). A parameter given as text (an
 * enum by its name, `plane_fit: road_surface`, as parameter files for the core take it) is put
 * back as the number dynamic_reconfigure reads, which would otherwise ignore it without a word;
 * text that is no value of the parameter is removed (the preset's value is used) and listed in
 * ModePreset::invalid for the caller's error.
 */
ModePreset applyModePreset(ros::NodeHandle& pnh, const std::string& mode);

/**
 * @brief A reconfigure request as the detector's Params: @p base (keeping its
 * non-reconfigurable fields, the up axis) with every Config field, sanitised; @p config gets
 * the repaired values back (odd windows...), so that rqt_reconfigure shows them.
 * @param[out] unmapped number of Config fields without a Params field (0 unless cfg and
 * params.def disagree).
 */
Params paramsFromConfig(LaneDetectorConfig& config, const Params& base, int& unmapped);

/**
 * @brief The detector's dynamic_reconfigure server: every change (and the initial values, at
 * construction) reaches @p apply as sanitised Params, on the server's thread.
 */
class DetectorReconfigure {
 public:
  /// @p apply gets the Params and the number of unmapped Config fields (paramsFromConfig()).
  DetectorReconfigure(ros::NodeHandle& pnh, std::function<void(const Params&, int)> apply);

 private:
  std::function<void(const Params&, int)> apply_;
  Params params_;                  ///< the latest sanitised Config (server callbacks only)
  boost::recursive_mutex mutex_;   ///< the server's own lock
  std::unique_ptr<dynamic_reconfigure::Server<LaneDetectorConfig>> server_;  ///< last
};

}  // namespace rgbd_lane_detector
