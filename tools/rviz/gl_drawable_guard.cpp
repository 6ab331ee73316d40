// LD_PRELOAD guard for rviz on software OpenGL (Mesa's swrast/llvmpipe through GLX, e.g. under
// Xvfb): Mesa's GLX loader sizes a drawable's buffers from XGetGeometry without checking that it
// succeeded (glx/drisw_glx.c, swrastGetDrawableInfo), so rendering into a window the X server
// does not know (not yet created there: Ogre creates render windows on one X connection and
// renders on another; or already destroyed: rviz shutting down) sizes them from uninitialised
// stack values, and llvmpipe writes past the allocation: heap corruption ("free(): invalid next
// size", "double free or corruption") or a crash in Ogre. This library reports a failed
// XGetGeometry as a 1x1 drawable at the origin (still returning the failure, which every other
// caller checks), so such a frame renders into a pixel instead of past the heap block.
// See docs/RELIABILITY.md ("rviz under load"). Used by test/launch/test_rviz_demo.py through
// demo.launch's rviz_prefix argument.
#include <dlfcn.h>

#include <X11/Xlib.h>

namespace {

using GetGeometryFn = Status (*)(Display*, Drawable, Window*, int*, int*, unsigned*, unsigned*,
                                 unsigned*, unsigned*);

GetGeometryFn realGetGeometry() {
  static const GetGeometryFn real =
      reinterpret_cast<GetGeometryFn>(dlsym(RTLD_NEXT, "XGetGeometry"));
  return real;
}

}  // namespace

extern "C" Status XGetGeometry(Display* display, Drawable drawable, Window* root, int* x, int* y,
                               unsigned* width, unsigned* height, unsigned* border,
                               unsigned* depth) {
  const GetGeometryFn real = realGetGeometry();
  const Status status =
      real ? real(display, drawable, root, x, y, width, height, border, depth) : 0;
  if (status == 0) {  // BadDrawable (or no libX11): a defined, tiny geometry
    if (x) *x = 0;
    if (y) *y = 0;
    if (width) *width = 1;
    if (height) *height = 1;
    if (border) *border = 0;
  }
  return status;
}
