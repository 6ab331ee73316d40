#include "rgbd_lane_detector_tools/dataset/bag_writer.h"

#include <cmath>
#include <limits>

#include <cv_bridge/cv_bridge.h>
#include <geometry_msgs/TransformStamped.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2_msgs/TFMessage.h>
#include <opencv2/imgproc.hpp>

#include "rgbd_lane_detector/ros/conversions.h"

namespace rgbd_lane_detector {
namespace tools {
namespace {

namespace enc = sensor_msgs::image_encodings;

std::string joinTopic(const std::string& ns, const std::string& name) {
  if (ns.empty() || ns == "/") return "/" + name;
  std::string n = ns[0] == '/' ? ns : "/" + ns;
  if (n.back() == '/') n.pop_back();
  return n + "/" + name;
}

}  // namespace

BagWriter::BagWriter() = default;
BagWriter::~BagWriter() {
  close();
}

void BagWriter::depthToMillimetres(const cv::Mat& depth, double scale, cv::Mat& out) {
  out.create(depth.size(), CV_16UC1);
  for (int y = 0; y < depth.rows; ++y) {
    uint16_t* o = out.ptr<uint16_t>(y);
    for (int x = 0; x < depth.cols; ++x) {
      double m;
      if (depth.type() == CV_16UC1) {
        const uint16_t raw = depth.at<uint16_t>(y, x);
        m = raw ? raw * scale : 0.0;
      } else {
        m = depth.at<float>(y, x);
      }
      const double mm = std::round(m * 1000.0);
      o[x] = (std::isfinite(mm) && mm > 0.0 && mm <= 65535.0) ? static_cast<uint16_t>(mm) : 0;
    }
  }
}

void BagWriter::depthToMetres(const cv::Mat& depth, double scale, cv::Mat& out) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  out.create(depth.size(), CV_32FC1);
  for (int y = 0; y < depth.rows; ++y) {
    float* o = out.ptr<float>(y);
    for (int x = 0; x < depth.cols; ++x) {
      float m;
      if (depth.type() == CV_16UC1) {
        const uint16_t raw = depth.at<uint16_t>(y, x);
        m = raw ? static_cast<float>(raw * scale) : nan;
      } else {
        m = depth.at<float>(y, x);
      }
      o[x] = (std::isfinite(m) && m > 0.f) ? m : nan;
    }
  }
}

bool BagWriter::open(const std::string& path, const BagWriterOptions& options, std::string& error) {
  close();
  options_ = options;
  count_ = 0;
  if (!(options.rate > 0)) {
    error = "bag rate must be > 0 Hz";
    return false;
  }
  try {
    bag_ = std::make_unique<rosbag::Bag>();
    bag_->open(path, rosbag::bagmode::Write);
    if (options.compress) bag_->setCompression(rosbag::compression::LZ4);
  } catch (const rosbag::BagException& e) {
    bag_.reset();
    error = "cannot create bag " + path + ": " + e.what();
    return false;
  }
  return true;
}

bool BagWriter::write(const DatasetFrame& f, std::string& error) {
  if (!bag_) {
    error = "bag not open";
    return false;
  }
  if (f.colour.empty() || f.depth.empty() ||
      (f.depth.type() != CV_16UC1 && f.depth.type() != CV_32FC1)) {
    error = "frame " + f.name + ": missing colour or unsupported depth";
    return false;
  }
  const double t =
      options_.use_source_stamps ? f.stamp : options_.start_time + count_ / options_.rate;
  if (!(t > 0) || !std::isfinite(t)) {
    error = "frame " + f.name + ": invalid stamp (use synthesised stamps)";
    return false;
  }
  const ros::Time stamp(t);
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = options_.frame_id;
  header.seq = static_cast<uint32_t>(count_);
  try {
    if (count_ == 0 && !options_.tf_parent.empty()) {
      geometry_msgs::TransformStamped tf;
      tf.header.stamp = stamp;
      tf.header.frame_id = options_.tf_parent;
      tf.child_frame_id = options_.frame_id;
      tf.transform.translation.x = options_.tf_x;
      tf.transform.translation.y = options_.tf_y;
      tf.transform.translation.z = options_.tf_z;
      tf2::Quaternion body, optical;
      body.setRPY(options_.tf_roll, options_.tf_pitch, options_.tf_yaw);
      optical.setValue(-0.5, 0.5, -0.5, 0.5);  // x-forward body -> optical (z fwd, y down)
      const tf2::Quaternion q = (body * optical).normalized();
      tf.transform.rotation.x = q.x();
      tf.transform.rotation.y = q.y();
      tf.transform.rotation.z = q.z();
      tf.transform.rotation.w = q.w();
      tf2_msgs::TFMessage msg;
      msg.transforms.push_back(tf);
      // a custom connection header replaces rosbag's: it must carry the type fields too
      using Traits = tf2_msgs::TFMessage;
      auto latched = boost::make_shared<ros::M_string>();
      (*latched)["type"] = ros::message_traits::datatype<Traits>();
      (*latched)["md5sum"] = ros::message_traits::md5sum<Traits>();
      (*latched)["message_definition"] = ros::message_traits::definition<Traits>();
      (*latched)["latching"] = "1";
      (*latched)["callerid"] = "/sequence_to_bag";
      bag_->write("/tf_static", stamp, msg, latched);
    }
    // colour
    std::string encoding;
    cv::Mat colour = f.colour;
    switch (f.format) {
      case PixelFormat::kBgr8:
        encoding = enc::BGR8;
        break;
      case PixelFormat::kRgb8:
        encoding = enc::RGB8;
        break;
      case PixelFormat::kBgra8:
        encoding = enc::BGRA8;
        break;
      case PixelFormat::kRgba8:
        encoding = enc::RGBA8;
        break;
      case PixelFormat::kMono8:
        encoding = enc::MONO8;
        break;
    }
    if (options_.rgb8 && f.format == PixelFormat::kBgr8) {
      cv::cvtColor(f.colour, colour, cv::COLOR_BGR2RGB);
      encoding = enc::RGB8;
    }
    bag_->write(joinTopic(options_.ns, "rgb/image_rect_color"), stamp,
                *cv_bridge::CvImage(header, encoding, colour).toImageMsg());
    // depth
    cv::Mat depth;
    if (options_.depth_float) {
      depthToMetres(f.depth, f.depth_scale, depth);
      bag_->write(joinTopic(options_.ns, "depth_registered/image_rect"), stamp,
                  *cv_bridge::CvImage(header, enc::TYPE_32FC1, depth).toImageMsg());
    } else {
      depthToMillimetres(f.depth, f.depth_scale, depth);
      bag_->write(joinTopic(options_.ns, "depth_registered/image_rect"), stamp,
                  *cv_bridge::CvImage(header, enc::TYPE_16UC1, depth).toImageMsg());
    }
    // camera_info
    const sensor_msgs::CameraInfo info =
        conversions::cameraInfoFromIntrinsics(f.intrinsics, f.colour.cols, f.colour.rows, header);
    bag_->write(joinTopic(options_.ns, "rgb/camera_info"), stamp, info);
  } catch (const rosbag::BagException& e) {
    error = std::string("cannot write to bag: ") + e.what();
    return false;
  } catch (const cv::Exception& e) {
    error = std::string("cannot convert frame: ") + e.what();
    return false;
  }
  ++count_;
  return true;
}

void BagWriter::close() {
  if (bag_) {
    try {
      bag_->close();
    } catch (const rosbag::BagException&) {
    }
    bag_.reset();
  }
}

}  // namespace tools
}  // namespace rgbd_lane_detector
