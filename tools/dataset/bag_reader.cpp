// rosbag input: colour + registered depth + camera_info, paired by header stamp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <string>
#include <utility>

#include <cv_bridge/cv_bridge.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include "readers_internal.h"
#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace tools {
namespace internal {
namespace {

namespace enc = sensor_msgs::image_encodings;

// "rgb/image_rect_color" matches "/camera/rgb/image_rect_color"; "/x/y" must match exactly.
bool topicMatches(const std::string& topic, const std::string& wanted) {
  if (wanted.empty()) return false;
  if (wanted[0] == '/') return topic == wanted;
  return topic == wanted || topic == "/" + wanted ||
         (topic.size() > wanted.size() + 1 &&
          topic.compare(topic.size() - wanted.size(), wanted.size(), wanted) == 0 &&
          topic[topic.size() - wanted.size() - 1] == '/');
}

class BagReader : public DatasetReader {
 public:
  const char* kind() const override { return "bag"; }
  int size() const override { return size_; }

  bool open(const DatasetOptions& o, std::string& error) {
    options_ = o;
    try {
      bag_.open(o.path, rosbag::bagmode::Read);
      rosbag::View all(bag_);
      std::vector<std::string> found;
      std::string colour_type, depth_type, info_type;
      for (const rosbag::ConnectionInfo* c : all.getConnections()) {
        if (topicMatches(c->topic, o.colour_topic)) {
          colour_topic_ = c->topic;
          colour_type = c->datatype;
        } else if (topicMatches(c->topic, o.depth_topic)) {
          depth_topic_ = c->topic;
          depth_type = c->datatype;
        } else if (topicMatches(c->topic, o.info_topic)) {
          info_topic_ = c->topic;
          info_type = c->datatype;
        }
        found.push_back(c->topic);
      }
      std::string list;
      for (const auto& t : found) list += " " + t;
      if (colour_topic_.empty() || depth_topic_.empty()) {
        error = "bag " + o.path + " has no topic matching '" +
                (colour_topic_.empty() ? o.colour_topic : o.depth_topic) +
                "' (--colour-topic, --depth-topic; topics:" + list + ")";
        return false;
      }
      // a compressed stream (sensor_msgs/CompressedImage) is not read: said, not skipped
      const std::pair<const std::string*, const std::string*> images[] = {
          {&colour_topic_, &colour_type}, {&depth_topic_, &depth_type}};
      for (const auto& t : images) {
        if (*t.second == "sensor_msgs/Image") continue;
        error = "bag " + o.path + ": topic " + *t.first + " holds " + *t.second +
                ", not sensor_msgs/Image (a compressed stream: republish it raw while playing the "
                "bag, rosrun image_transport republish compressed in:=<topic> raw out:=<topic>, "
                "and record that)";
        return false;
      }
      if (!info_topic_.empty() && info_type != "sensor_msgs/CameraInfo") {
        error = "bag " + o.path + ": topic " + info_topic_ + " holds " + info_type +
                ", not sensor_msgs/CameraInfo (--info-topic, or --camera-info with a YAML)";
        return false;
      }
      if (!o.camera_info.empty()) {
        if (!applyCameraInfo(o, K_override_, error)) return false;
        have_override_ = true;
      } else if (info_topic_.empty()) {
        error = "bag " + o.path + " has no topic matching '" + o.info_topic +
                "' (--info-topic); or pass a camera_info YAML, --camera-info (topics:" + list + ")";
        return false;
      }
      rosbag::View colour(bag_, rosbag::TopicQuery(colour_topic_));
      const int n = static_cast<int>(colour.size());
      const int step = std::max(1, o.step);
      int avail = std::max(0, (n - std::max(0, o.first) + step - 1) / step);
      if (o.max_frames >= 0) avail = std::min(avail, o.max_frames);
      size_ = avail;
      std::vector<std::string> topics = {colour_topic_, depth_topic_};
      if (!info_topic_.empty()) topics.push_back(info_topic_);
      view_ = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(topics));
      it_ = view_->begin();
    } catch (const rosbag::BagException& e) {
      error = "cannot read bag " + o.path + ": " + e.what();
      return false;
    }
    return true;
  }

  bool next(DatasetFrame& f) override {
    try {
      while (true) {
        sensor_msgs::ImageConstPtr c, d;
        if (pairReady(c, d)) {
          ++pairs_;
          if (pairs_ - 1 < options_.first ||
              (pairs_ - 1 - options_.first) % std::max(1, options_.step))
            continue;
          if (options_.max_frames >= 0 && emitted_ >= options_.max_frames) return false;
          if (!convert(c, d, f)) return false;
          f.index = pairs_ - 1;
          ++emitted_;
          return true;
        }
        if (it_ == view_->end()) {
          if (!at_end_) {  // the last colour images pair with what depth is left
            at_end_ = true;
            continue;
          }
          if (!have_info_ && !have_override_ && error_.empty())
            error_ = "no camera_info on " + info_topic_ +
                     " with a usable P or K (all zero?): pass --camera-info with a YAML";
          return false;
        }
        const rosbag::MessageInstance m = *it_;  // a copy: incrementing frees the iterator's
        ++it_;
        if (m.getTopic() == info_topic_) {
          const auto info = m.instantiate<sensor_msgs::CameraInfo>();
          if (info) {
            const Intrinsics k = conversions::intrinsicsFromCameraInfo(*info);  // P, else K
            if (k.valid()) {
              K_ = k;
              have_info_ = true;
            }
            if (conversions::hasDistortion(*info) && !warned_distortion_) {
              warned_distortion_ = true;
              std::fprintf(stderr,
                           "bag reader: warning: camera_info on %s has distortion coefficients "
                           "(model '%s'): the images of %s are read as rectified, with %s. Record "
                           "rectified images (image_proc's image_rect_color) for lines in place "
                           "toward the image edges.\n",
                           info_topic_.c_str(), info->distortion_model.c_str(),
                           colour_topic_.c_str(), info->P[0] != 0.0 ? "P" : "K");
            }
          }
        } else if (m.getTopic() == colour_topic_) {
          if (auto img = m.instantiate<sensor_msgs::Image>()) colours_.push_back(img);
        } else if (m.getTopic() == depth_topic_) {
          if (auto img = m.instantiate<sensor_msgs::Image>()) depths_.push_back(img);
        }
        // bound memory when one stream never pairs
        while (colours_.size() > 60) colours_.pop_front();
        while (depths_.size() > 60) depths_.pop_front();
      }
    } catch (const rosbag::BagException& e) {
      error_ = std::string("bag read error: ") + e.what();
    }
    return false;
  }

 private:
  // Pair the oldest colour image with the depth image closest in time (within tolerance),
  // once intrinsics are known and no later depth can be closer: one stamped at or after the
  // colour image is in (stamps grow through the bag), or the bag has ended.
  bool pairReady(sensor_msgs::ImageConstPtr& c, sensor_msgs::ImageConstPtr& d) {
    if (!have_info_ && !have_override_) return false;
    while (!colours_.empty() && !depths_.empty()) {
      const double tc = colours_.front()->header.stamp.toSec();
      size_t best = 0;
      double best_dt = 1e18;
      for (size_t i = 0; i < depths_.size(); ++i) {
        const double dt = std::fabs(depths_[i]->header.stamp.toSec() - tc);
        if (dt < best_dt) {
          best_dt = dt;
          best = i;
        }
      }
      const double last_depth = depths_.back()->header.stamp.toSec();
      if (best_dt <= options_.sync_tolerance && !at_end_ && last_depth < tc) return false;
      if (best_dt <= options_.sync_tolerance) {
        c = colours_.front();
        d = depths_[best];
        colours_.pop_front();
        depths_.erase(depths_.begin(), depths_.begin() + best + 1);
        return true;
      }
      // a later depth may still match; decide only when depth is past this colour frame
      if (at_end_ || last_depth > tc + options_.sync_tolerance) {
        colours_.pop_front();
      } else {
        return false;
      }
    }
    return false;
  }

  bool convert(const sensor_msgs::ImageConstPtr& c, const sensor_msgs::ImageConstPtr& d,
               DatasetFrame& f) {
    try {
      const std::string& e = c->encoding;
      if (e == enc::BGR8 || e == enc::RGB8 || e == enc::BGRA8 || e == enc::RGBA8 ||
          e == enc::MONO8) {
        f.colour = cv_bridge::toCvCopy(c)->image;
        f.format = e == enc::BGR8    ? PixelFormat::kBgr8
                   : e == enc::RGB8  ? PixelFormat::kRgb8
                   : e == enc::BGRA8 ? PixelFormat::kBgra8
                   : e == enc::RGBA8 ? PixelFormat::kRgba8
                                     : PixelFormat::kMono8;
      } else {
        f.colour = cv_bridge::toCvCopy(c, enc::BGR8)->image;
        f.format = PixelFormat::kBgr8;
      }
      if (d->width != c->width || d->height != c->height) {
        error_ = "the depth image on " + depth_topic_ + " is " + std::to_string(d->width) + "x" +
                 std::to_string(d->height) + ", the colour image on " + colour_topic_ + " " +
                 std::to_string(c->width) + "x" + std::to_string(c->height) +
                 ": the depth must be registered to the colour camera, pixel for pixel "
                 "(RealSense: aligned_depth_to_color/image_raw; --depth-topic)";
        return false;
      }
      if (d->encoding == enc::TYPE_16UC1 || d->encoding == enc::MONO16) {
        f.depth = cv_bridge::toCvCopy(d)->image;
        f.depth_scale = options_.depth_scale > 0 ? options_.depth_scale : 0.001;
      } else if (d->encoding == enc::TYPE_32FC1) {
        f.depth = cv_bridge::toCvCopy(d)->image;
        f.depth_scale = 1.0;
      } else {
        error_ = "unsupported depth encoding '" + d->encoding + "' (16UC1 mm or 32FC1 m)";
        return false;
      }
    } catch (const cv_bridge::Exception& ex) {
      error_ = std::string("cannot convert bag image: ") + ex.what();
      return false;
    }
    f.intrinsics = have_override_ ? K_override_ : K_;
    f.stamp = c->header.stamp.toSec();
    char name[48];
    std::snprintf(name, sizeof(name), "%.6f", f.stamp);
    f.name = name;
    return true;
  }

  DatasetOptions options_;
  rosbag::Bag bag_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  std::string colour_topic_, depth_topic_, info_topic_;
  std::deque<sensor_msgs::ImageConstPtr> colours_, depths_;
  Intrinsics K_, K_override_;
  bool have_info_ = false, have_override_ = false;
  bool at_end_ = false;             ///< the bag was read to its end
  bool warned_distortion_ = false;
  int size_ = -1;
  int pairs_ = 0;
  int emitted_ = 0;
};

}  // namespace

std::unique_ptr<DatasetReader> openBag(const DatasetOptions& o, std::string& error) {
  auto reader = std::make_unique<BagReader>();
  if (!reader->open(o, error)) return nullptr;
  return reader;
}

}  // namespace internal
}  // namespace tools
}  // namespace rgbd_lane_detector
