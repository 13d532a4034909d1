// SPDX-License-Identifier: MIT
// PNG codecs on libpng: 16-bit single-channel depth (BOP depth frames) and
// 8-bit grey/RGB pictures. libpng reports errors by longjmp, so every libpng
// call happens inside small setjmp-protected stages whose frames hold no
// objects with destructors; C++ state lives in the callers.

#include <bit>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <png.h>
#include <sys/stat.h>

#include "core/dataset/atomic_file.h"
#include "core/dataset/bop_io.h"

namespace ihf {

namespace {

constexpr bool kLittleEndian = std::endian::native == std::endian::little;

struct PngErrorState {
	char message[256] = "unknown libpng error";
	std::FILE *out = nullptr; // writing: the stream, so errno can be kept
};

void onPngError(png_structp png, png_const_charp msg)
{
	auto *state = static_cast<PngErrorState *>(png_get_error_ptr(png));
	std::snprintf(state->message, sizeof(state->message), "%s", msg);
	png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp)
{
	// Warnings (e.g. unknown ancillary chunks) do not affect the samples.
}

// Replaces libpng's writer so the message says why ("File too large"), not
// only "Write Error".
void onPngWrite(png_structp png, png_bytep data, size_t length)
{
	auto *state = static_cast<PngErrorState *>(png_get_io_ptr(png));
	if (std::fwrite(data, 1, length, state->out) != length)
		png_error(png, std::strerror(errno));
}

void onPngFlush(png_structp png)
{
	auto *state = static_cast<PngErrorState *>(png_get_io_ptr(png));
	std::fflush(state->out);
}

struct PngHeader {
	png_uint_32 width = 0;
	png_uint_32 height = 0;
	int bitDepth = 0;
	int colorType = 0;
	int interlace = 0;
};

const char *colorTypeName(int type)
{
	switch (type) {
	case PNG_COLOR_TYPE_GRAY: return "grey";
	case PNG_COLOR_TYPE_RGB: return "RGB";
	case PNG_COLOR_TYPE_PALETTE: return "palette";
	case PNG_COLOR_TYPE_GRAY_ALPHA: return "grey+alpha";
	case PNG_COLOR_TYPE_RGB_ALPHA: return "RGBA";
	}
	return "unknown colour type";
}

// Limits on what a PNG may make libpng allocate before a pixel is read:
// its image size, and the ancillary chunks (text, ICC profiles, unknown
// chunks) it keeps in memory; depth frames need none of those.
constexpr png_uint_32 kMaxSide = 1u << 15;
constexpr png_alloc_size_t kMaxChunkBytes = 1u << 20;
constexpr png_uint_32 kMaxAncillaryChunks = 64;
// zlib's deflate cannot compress better than 1032:1, so the decoded image
// of a file of n bytes has at most 1032 n bytes.
constexpr uint64_t kMaxDeflateRatio = 1032;

// libpng allocates an ancillary chunk's claimed length before reading it
// and only warns when that passes png_set_chunk_malloc_max(); its own
// buffers while reading a depth frame (a row, zlib's window) are far below
// this. A larger request fails, which libpng reports as an error.
constexpr png_alloc_size_t kMaxLibpngAllocation = 4u << 20;

png_voidp boundedPngMalloc(png_structp, png_alloc_size_t size)
{
	return size <= kMaxLibpngAllocation ? std::malloc(size) : nullptr;
}

void pngFree(png_structp, png_voidp p)
{
	std::free(p);
}

bool readHeaderStage(png_structp png, png_infop info, std::FILE *fp, PngHeader *h)
{
	if (setjmp(png_jmpbuf(png)))
		return false;
	png_set_user_limits(png, kMaxSide, kMaxSide);
	png_set_chunk_malloc_max(png, kMaxChunkBytes);
	png_set_chunk_cache_max(png, kMaxAncillaryChunks);
	png_init_io(png, fp);
	png_set_sig_bytes(png, 8);
	png_read_info(png, info);
	png_get_IHDR(png, info, &h->width, &h->height, &h->bitDepth, &h->colorType,
		     &h->interlace, nullptr, nullptr);
	return true;
}

bool prepareStage(png_structp png, png_infop info, size_t *rowBytes)
{
	if (setjmp(png_jmpbuf(png)))
		return false;
	// PNG stores 16-bit samples big-endian.
	if (kLittleEndian)
		png_set_swap(png);
	png_set_interlace_handling(png);
	png_read_update_info(png, info);
	*rowBytes = png_get_rowbytes(png, info);
	return true;
}

bool readImageStage(png_structp png, png_bytep *rows)
{
	if (setjmp(png_jmpbuf(png)))
		return false;
	png_read_image(png, rows);
	return true;
}

bool readEndStage(png_structp png)
{
	if (setjmp(png_jmpbuf(png)))
		return false;
	png_read_end(png, nullptr);
	return true;
}

bool writeStage(png_structp png, png_infop info, PngErrorState *state, png_uint_32 width,
		png_uint_32 height, int bitDepth, int colorType, png_bytep *rows)
{
	if (setjmp(png_jmpbuf(png)))
		return false;
	png_set_write_fn(png, state, onPngWrite, onPngFlush);
	png_set_IHDR(png, info, width, height, bitDepth, colorType, PNG_INTERLACE_NONE,
		     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	// Frames are written by the thousand (synthesis): zlib level 1 with the
	// Paeth filter writes a 640x480 depth frame ~3x faster than the defaults
	// for ~1.3x the bytes.
	png_set_compression_level(png, 1);
	png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_PAETH);
	png_write_info(png, info);
	if (bitDepth == 16 && kLittleEndian)
		png_set_swap(png);
	png_write_image(png, rows);
	png_write_end(png, info);
	return true;
}

struct FileCloser {
	void operator()(std::FILE *f) const { std::fclose(f); }
};

Status writePng(const fs::path &file, png_uint_32 width, png_uint_32 height, int bitDepth,
		int colorType, const std::vector<png_bytep> &rows)
{
	return writeFileAtomic(file, [&](std::FILE *fp) -> Status {
		PngErrorState state;
		state.out = fp;
		png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state,
							  onPngError, onPngWarning);
		png_infop info = png ? png_create_info_struct(png) : nullptr;
		if (!info) {
			png_destroy_write_struct(&png, nullptr);
			return makeError(Errc::kIo, file.string() + ": cannot initialise libpng");
		}
		bool ok = writeStage(png, info, &state, width, height, bitDepth, colorType,
				     const_cast<png_bytep *>(rows.data()));
		png_destroy_write_struct(&png, &info);
		if (!ok)
			return makeError(Errc::kIo, file.string() + ": PNG write failed: " +
						    state.message);
		return {};
	});
}

} // namespace

Expected<DepthImage16> readDepthPng(const fs::path &file)
{
	std::unique_ptr<std::FILE, FileCloser> fp(std::fopen(file.c_str(), "rb"));
	if (!fp) {
		std::error_code ec;
		if (!fs::exists(file, ec))
			return makeError(Errc::kNotFound, file.string() + ": depth image not found");
		return makeError(Errc::kIo, file.string() + ": cannot open for reading");
	}

	png_byte sig[8];
	if (std::fread(sig, 1, sizeof(sig), fp.get()) != sizeof(sig) ||
	    png_sig_cmp(sig, 0, sizeof(sig)) != 0)
		return makeError(Errc::kParse, file.string() + ": not a PNG file");

	PngErrorState state;
	png_structp png = png_create_read_struct_2(PNG_LIBPNG_VER_STRING, &state, onPngError, onPngWarning,
						   nullptr, boundedPngMalloc, pngFree);
	png_infop info = png ? png_create_info_struct(png) : nullptr;
	struct ReadGuard {
		png_structp *png;
		png_infop *info;
		~ReadGuard() { png_destroy_read_struct(png, info, nullptr); }
	} guard{&png, &info};
	if (!info)
		return makeError(Errc::kIo, file.string() + ": cannot initialise libpng");

	PngHeader h;
	if (!readHeaderStage(png, info, fp.get(), &h))
		return makeError(Errc::kCorrupt, file.string() + ": bad PNG header: " + state.message);
	if (h.bitDepth != 16 || h.colorType != PNG_COLOR_TYPE_GRAY)
		return makeError(Errc::kUnsupported,
				 file.string() + ": not a 16-bit single-channel PNG (it is " +
					 std::to_string(h.bitDepth) + "-bit " +
					 colorTypeName(h.colorType) + ")");
	// Guards the int-sized Image and absurd allocations from a corrupt header.
	if (h.width > kMaxSide || h.height > kMaxSide)
		return makeError(Errc::kUnsupported, file.string() + ": image " +
							     std::to_string(h.width) + "x" +
							     std::to_string(h.height) + " too large");
	// A header claiming more pixels than the file's bytes can inflate to is
	// refused before the image is allocated.
	struct stat st;
	const uint64_t rowsBytes = uint64_t{h.height} * (1 + 2 * uint64_t{h.width});
	if (::fstat(::fileno(fp.get()), &st) == 0 &&
	    rowsBytes > kMaxDeflateRatio * static_cast<uint64_t>(st.st_size))
		return makeError(Errc::kCorrupt, file.string() + ": header claims a " + std::to_string(h.width) + "x" +
							 std::to_string(h.height) + " image, more than the file's " +
							 std::to_string(st.st_size) + " bytes can hold (truncated?)");

	DepthImage16 image(static_cast<int>(h.width), static_cast<int>(h.height));
	std::vector<png_bytep> rows(h.height);
	for (png_uint_32 y = 0; y < h.height; ++y)
		rows[y] = reinterpret_cast<png_bytep>(image.data() + static_cast<size_t>(y) * h.width);

	size_t rowBytes = 0;
	if (!prepareStage(png, info, &rowBytes))
		return makeError(Errc::kCorrupt, file.string() + ": bad PNG header: " + state.message);
	if (rowBytes != h.width * sizeof(uint16_t))
		return makeError(Errc::kCorrupt, file.string() + ": unexpected PNG row size");
	if (!readImageStage(png, rows.data()))
		return makeError(Errc::kCorrupt, file.string() + ": bad PNG data: " + state.message);
	// Also checks the trailing chunks and CRCs: a damaged file is an error even
	// when all rows decoded.
	if (!readEndStage(png))
		return makeError(Errc::kCorrupt, file.string() + ": bad PNG trailer: " + state.message);
	return image;
}

Status writeDepthPng(const fs::path &file, const DepthImage16 &image)
{
	if (image.empty() || image.width() <= 0 || image.height() <= 0)
		return makeError(Errc::kInvalidArgument, file.string() + ": cannot write an empty depth image");
	std::vector<png_bytep> rows(image.height());
	for (int y = 0; y < image.height(); ++y)
		rows[y] = reinterpret_cast<png_bytep>(const_cast<uint16_t *>(&image.at(0, y)));
	return writePng(file, image.width(), image.height(), 16, PNG_COLOR_TYPE_GRAY, rows);
}

Status writePng8(const fs::path &file, int width, int height, int channels, const uint8_t *pixels)
{
	if (width <= 0 || height <= 0 || !pixels)
		return makeError(Errc::kInvalidArgument, file.string() + ": cannot write an empty picture");
	if (channels != 1 && channels != 3)
		return makeError(Errc::kInvalidArgument, file.string() + ": " + std::to_string(channels) +
								 " channels, expected 1 (grey) or 3 (RGB)");
	std::vector<png_bytep> rows(height);
	for (int y = 0; y < height; ++y)
		rows[y] = const_cast<png_bytep>(pixels + static_cast<size_t>(y) * width * channels);
	return writePng(file, width, height, 8,
			channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, rows);
}

} // namespace ihf
