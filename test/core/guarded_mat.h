// Image memory that ends at an inaccessible page, for the tests of kernels whose loads must stay
// inside a source row: a read past the image's last byte faults (an over-read of an ordinary
// cv::Mat lands in its allocation's padding unseen).
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace rgbd_lane_detector {
namespace test {

/// A continuous rows x cols image of a type whose last row ends where a PROT_NONE page begins.
class GuardedMat {
 public:
  GuardedMat(int rows, int cols, int type) {
    const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    const size_t bytes = static_cast<size_t>(rows) * cols * CV_ELEM_SIZE(type);
    const size_t data_pages = (bytes + page - 1) / page * page;
    length_ = data_pages + page;
    void* base = mmap(nullptr, length_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (base == MAP_FAILED) {
      ADD_FAILURE() << "mmap of " << length_ << " bytes failed";
      base_ = nullptr;
      return;
    }
    base_ = static_cast<uint8_t*>(base);
    if (mprotect(base_ + data_pages, page, PROT_NONE) != 0)
      ADD_FAILURE() << "mprotect of the guard page failed";
    guard_ = base_ + data_pages;
    mat_ = cv::Mat(rows, cols, type, guard_ - bytes);  // (step: no padding)
  }
  /// A copy of @p image in guarded memory.
  explicit GuardedMat(const cv::Mat& image) : GuardedMat(image.rows, image.cols, image.type()) {
    if (!base_) return;
    image.copyTo(mat_);  // (the same size and type: into the guarded memory)
    EXPECT_EQ(end(), guard_) << "the image left the guarded memory";
  }
  ~GuardedMat() {
    if (base_) munmap(base_, length_);
  }
  GuardedMat(const GuardedMat&) = delete;
  GuardedMat& operator=(const GuardedMat&) = delete;

  /// The image (empty when the memory could not be mapped).
  const cv::Mat& mat() const { return mat_; }
  /// One past the image's last byte (the guard page's first while the image is in place).
  const uint8_t* end() const { return mat_.data + mat_.total() * mat_.elemSize(); }
  /// The guard page's first byte.
  const uint8_t* guard() const { return guard_; }

 private:
  uint8_t* base_ = nullptr;
  uint8_t* guard_ = nullptr;
  size_t length_ = 0;
  cv::Mat mat_;
};

}  // namespace test
}  // namespace rgbd_lane_detector
