#include "pipeline/image_io/png_file.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <new>

namespace texsim {

namespace {

// libpng reports errors by longjmp: the functions that call setjmp below hold only trivially
// destructible locals, and every C++ object they fill belongs to their caller.
struct Context {
  const uint8_t* data = nullptr;  // reading: the file's bytes
  size_t size = 0, pos = 0;
  int os_errno = 0;  // writing: errno when libpng gave up
  char message[256] = {};
};

void on_error(png_structp png, png_const_charp msg) {
  auto* c = static_cast<Context*>(png_get_error_ptr(png));
  c->os_errno = errno;
  std::snprintf(c->message, sizeof c->message, "%s", msg);
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}  // benign: the image is still read

void read_from_memory(png_structp png, png_bytep out, png_size_t n) {
  auto* c = static_cast<Context*>(png_get_io_ptr(png));
  if (n > c->size - c->pos) png_error(png, "file ends before the image does");
  std::memcpy(out, c->data + c->pos, n);
  c->pos += n;
}

// Writes the PNG to an open file; false with the reason in c.message.
// `channels`: 3 (RGB) or 4 (RGBA).
bool encode(Context& c, std::FILE* f, int w, int h, const uint8_t* rgb, bool fast, int channels) {
  std::snprintf(c.message, sizeof c.message, "out of memory");  // until libpng says more
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &c, on_error, on_warning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(w), static_cast<png_uint_32>(h), 8,
               channels == 4 ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, fast ? 1 : 6);
  if (fast) png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_write_info(png, info);
  const size_t row = static_cast<size_t>(w) * static_cast<size_t>(channels);
  for (int y = 0; y < h; ++y)
    png_write_row(png, const_cast<png_bytep>(rgb + static_cast<size_t>(y) * row));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

// The header of a PNG in c.data: NotHandled for the kinds left to OpenImageIO, Failed when too
// large, else the size, the interlace passes and the transformations that make 8-bit RGB of it.
PngRead read_header(png_structp png, png_infop info, int max_side, int* w, int* h, int* passes) {
  png_read_info(png, info);
  const int depth = png_get_bit_depth(png, info);
  const int type = png_get_color_type(png, info);
  // Transparency (tRNS) becomes an alpha channel that OpenImageIO multiplies into the colour.
  if (png_get_valid(png, info, PNG_INFO_tRNS)) return PngRead::NotHandled;
  const bool palette = type == PNG_COLOR_TYPE_PALETTE;
  if (!(type == PNG_COLOR_TYPE_RGB && depth == 8) && !palette) return PngRead::NotHandled;
  *w = static_cast<int>(png_get_image_width(png, info));
  *h = static_cast<int>(png_get_image_height(png, info));
  if (*w > max_side || *h > max_side) return PngRead::Failed;
  if (palette) png_set_palette_to_rgb(png);  // also unpacks 1, 2 and 4-bit indices
  *passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (png_get_rowbytes(png, info) != static_cast<size_t>(*w) * 3) png_error(png, "bad row size");
  return PngRead::Ok;
}

// Decodes c.data into `out` (sized here); the kinds left to OpenImageIO come back NotHandled.
PngRead decode(Context& c, int max_side, PngImage* out) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &c, on_error, on_warning);
  if (!png) return PngRead::Failed;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return PngRead::Failed;
  }
  png_set_read_fn(png, &c, read_from_memory);
  int w = 0, h = 0, passes = 1;
  const PngRead kind = read_header(png, info, max_side, &w, &h, &passes);
  if (kind == PngRead::Failed) {
    std::snprintf(c.message, sizeof c.message, "image is %d x %d pixels, more than %d per side", w,
                  h, max_side);
  }
  if (kind != PngRead::Ok) {
    png_destroy_read_struct(&png, &info, nullptr);
    return kind;
  }
  out->width = w;
  out->height = h;
  try {
    out->rgb.assign(static_cast<size_t>(w) * static_cast<size_t>(h) * 3, 0);
  } catch (const std::bad_alloc&) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::snprintf(c.message, sizeof c.message, "out of memory for %d x %d pixels", w, h);
    return PngRead::Failed;
  }
  // Interlaced images: every pass goes over the whole image, adding its pixels to the rows.
  for (int p = 0; p < passes; ++p) {
    for (int y = 0; y < h; ++y)
      png_read_row(png, out->rgb.data() + static_cast<size_t>(y) * static_cast<size_t>(w) * 3,
                   nullptr);
  }
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return PngRead::Ok;
}

// The writers' common body: `channels` bytes per pixel.
std::string write_png(const std::string& path, int width, int height, const uint8_t* pixels,
                      bool fast, int channels) {
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return std::strerror(errno);
  Context c;
  const bool ok = encode(c, f, width, height, pixels, fast, channels);
  errno = 0;
  // Data still buffered is written here: a full disk shows up now, not in encode.
  const bool closed = std::fclose(f) == 0;
  if (ok && closed) return "";
  if (!ok) return c.os_errno ? std::strerror(c.os_errno) : std::string(c.message);
  return errno ? std::strerror(errno) : "cannot close the file";
}

}  // namespace

std::string write_png_rgb8(const std::string& path, int width, int height, const uint8_t* rgb,
                           bool fast) {
  return write_png(path, width, height, rgb, fast, 3);
}

std::string write_png_rgba8(const std::string& path, int width, int height, const uint8_t* rgba) {
  return write_png(path, width, height, rgba, false, 4);
}

bool is_png(const uint8_t* data, size_t size) { return size >= 8 && png_sig_cmp(data, 0, 8) == 0; }

PngRead read_png_rgb8(const uint8_t* data, size_t size, int max_side, PngImage* out,
                      std::string* error) {
  if (!is_png(data, size)) return PngRead::NotHandled;
  Context c;
  c.data = data;
  c.size = size;
  const PngRead r = decode(c, max_side, out);
  if (r == PngRead::Failed) {
    *error = c.message[0] ? c.message : "out of memory";
    out->rgb.clear();
  }
  return r;
}

}  // namespace texsim
