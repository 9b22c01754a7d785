#pragma once

// libpng's error and warning callbacks for the PNG reader and writer. libpng reports an error by
// calling its error callback, which must not return: it keeps the message and longjmps to the
// setjmp of the call that failed, so the function that calls setjmp holds no object with a
// destructor (what it fills belongs to its caller).

#include <png.h>

#include <cstdio>

namespace cambio::app {

/// libpng's error pointer: the message of the error that stopped it.
struct PngErrorText {
  char text[200] = "libpng failed";
};

inline void keep_png_error(png_structp png, png_const_charp message) {
  auto* error = static_cast<PngErrorText*>(png_get_error_ptr(png));
  std::snprintf(error->text, sizeof error->text, "%s", message);
  png_longjmp(png, 1);
}

/// Warnings (a bad CRC in an ancillary chunk, an unknown chunk) leave the pixels whole.
inline void ignore_png_warning(png_structp /*png*/, png_const_charp /*message*/) {}

}  // namespace cambio::app
