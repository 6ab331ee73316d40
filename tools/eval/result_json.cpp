#include "rgbd_lane_detector_tools/result_json.h"

#include <cmath>
#include <cstdio>

namespace rgbd_lane_detector {
namespace tools {
namespace {

void appendSideScore(std::string& out, const char* name, const SideScore& s) {
  out += ", \"";
  out += name;
  out += "\": {\"truth\": " + jsonString(s.truth ? boundaryKindName(s.true_kind) : "none") +
         ", \"outcome\": " + jsonString(sideOutcomeName(s.outcome)) +
         ", \"points\": " + std::to_string(s.points) +
         ", \"inliers\": " + std::to_string(s.inliers) +
         ", \"mean_lateral\": " + jsonNumber(s.mean_lateral) + "}";
}

void appendTrace(std::string& out, const char* name, const MarkerTrace& m) {
  out += "\"";
  out += name;
  out += "\": {\"found\": ";
  out += m.found ? "true" : "false";
  out += ", \"kind\": ";
  out += m.found ? jsonString(boundaryKindName(m.kind)) : "null";
  out += ", \"confidence\": " + jsonNumber(m.confidence);
  out += ", \"peak_score\": " + jsonNumber(m.peak_score);
  out += ", \"angle\": " + jsonNumber(m.angle);
  out += ", \"angle_valid\": ";
  out += m.angle_valid ? "true" : "false";
  out += ", \"seed\": [" + jsonNumber(m.seed.x) + ", " + jsonNumber(m.seed.y) + "]";
  out += ", \"valid_points\": " + std::to_string(m.num_valid_points);
  out += ", \"pixels\": [";
  for (size_t i = 0; i < m.pixels.size(); ++i) {
    if (i) out += ", ";
    out += "[" + jsonNumber(m.pixels[i].x) + ", " + jsonNumber(m.pixels[i].y) + "]";
  }
  out += "], \"points\": [";
  for (size_t i = 0; i < m.points.size(); ++i) {
    if (i) out += ", ";
    const auto& p = m.points[i];
    if (!p.allFinite()) {
      out += "null";
    } else {
      out += "[" + jsonNumber(p.x()) + ", " + jsonNumber(p.y()) + ", " + jsonNumber(p.z()) + "]";
    }
  }
  out += "], \"scores\": [";
  for (size_t i = 0; i < m.scores.size(); ++i) {
    if (i) out += ", ";
    out += jsonNumber(m.scores[i]);
  }
  out += "]}";
}

}  // namespace

std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string resultToJson(int frame, const std::string& name, double stamp, const Result& r,
                         const FrameScore* score) {
  std::string out = "{\"frame\": " + std::to_string(frame);
  out += ", \"name\": " + jsonString(name);
  out += ", \"stamp\": " + jsonNumber(stamp);
  out += ", \"status\": " + jsonString(r.status == Status::kOk ? "ok" : statusMessage(r.status));
  const StageTimings& t = r.timings;
  out += ", \"timings_ms\": {\"preprocess\": " + jsonNumber(t.preprocess) +
         ", \"points\": " + jsonNumber(t.points) + ", \"normals\": " + jsonNumber(t.normals) +
         ", \"matching\": " + jsonNumber(t.matching) + ", \"response\": " + jsonNumber(t.response) +
         ", \"road\": " + jsonNumber(t.road) + ", \"pca\": " + jsonNumber(t.pca) +
         ", \"tracing\": " + jsonNumber(t.tracing) + ", \"classify\": " + jsonNumber(t.classify) +
         ", \"plane\": " + jsonNumber(t.plane) + ", \"total\": " + jsonNumber(t.total) + "}";
  if (r.status == Status::kOk) {
    const PlaneEstimate& p = r.plane;
    out += ", \"plane\": {\"valid\": ";
    out += p.valid ? "true" : "false";
    if (p.valid) {
      out += ", \"normal\": [" + jsonNumber(p.normal.x()) + ", " + jsonNumber(p.normal.y()) + ", " +
             jsonNumber(p.normal.z()) + "], \"distance\": " + jsonNumber(p.distance) +
             ", \"rms\": " + jsonNumber(p.rms) + ", \"range\": " + jsonNumber(p.range);
    }
    out += "}, ";
    appendTrace(out, "left", r.left);
    out += ", ";
    appendTrace(out, "right", r.right);
  }
  if (score) {
    out += ", \"score\": {\"outcome\": " + jsonString(outcomeName(score->outcome)) +
           ", \"lane_required\": " + (score->lane_required ? "true" : "false") +
           ", \"plane_ok\": " + (score->plane_ok ? "true" : "false") +
           ", \"angle_error_deg\": " + jsonNumber(score->angle_error_deg) +
           ", \"offset_error\": " + jsonNumber(score->offset_error);
    appendSideScore(out, "left", score->left);
    appendSideScore(out, "right", score->right);
    out += "}";
  }
  return out + "}";
}

}  // namespace tools
}  // namespace rgbd_lane_detector
