// OpenEXR reading and writing through OpenEXR's C++ library: Debian 12's OpenEXR 3.1 C API
// cannot decode DWA, the compression of every real map we have.  This is the only C++ in
// lumis.  Every exception is caught here and becomes a status and a message; truncation
// is told apart from corruption by the input streams below, which record hitting the end.
#include "internal.h"

#include <half.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <cmath>

#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfTiledOutputFile.h>
#include <ImfVersion.h>

#include <cerrno>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <mutex>
#include <thread>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace
{

// Formats a message into the caller's sink (the C helper lumis__fail is variadic C).
lumis_status fail(const lumis_error_sink *sink, lumis_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
lumis_status fail(const lumis_error_sink *sink, lumis_status st, const char *fmt, ...)
{
    if (sink && sink->fn) {
        char msg[512];
        va_list ap;
        va_start(ap, fmt);
        std::vsnprintf(msg, sizeof msg, fmt, ap);
        va_end(ap);
        sink->fn(sink->user, st, msg);
    }
    return st;
}

// Stream base recording whether a read ran past the end of the data.
class CheckedIStream : public Imf::IStream
{
  public:
    CheckedIStream(const char *name, uint64_t size) : Imf::IStream(name), size(size) {}
    bool hit_end = false;
    const uint64_t size; // bytes in the whole file
};

class MemoryIStream final : public CheckedIStream
{
  public:
    MemoryIStream(const unsigned char *data, size_t size, const char *name)
        : CheckedIStream(name, size), data_(data), size_(size)
    {
    }
    bool read(char c[], int n) override
    {
        if (n < 0 || pos_ > size_ || static_cast<size_t>(n) > size_ - pos_) {
            hit_end = true;
            throw std::runtime_error("unexpected end of file");
        }
        std::memcpy(c, data_ + pos_, static_cast<size_t>(n));
        pos_ += static_cast<size_t>(n);
        return pos_ < size_;
    }
    uint64_t tellg() override { return pos_; }
    void seekg(uint64_t pos) override { pos_ = pos; } // reads past the end fail in read()
    void clear() override {}

  private:
    const unsigned char *data_;
    size_t size_;
    size_t pos_ = 0;
};

class FileIStream final : public CheckedIStream
{
  public:
    FileIStream(std::FILE *f, const char *name, uint64_t size) : CheckedIStream(name, size), f_(f)
    {
    }
    bool read(char c[], int n) override
    {
        if (n < 0) throw std::runtime_error("negative read size");
        size_t got = std::fread(c, 1, static_cast<size_t>(n), f_);
        if (got != static_cast<size_t>(n)) {
            if (std::ferror(f_)) throw std::runtime_error(std::strerror(errno));
            hit_end = true;
            throw std::runtime_error("unexpected end of file");
        }
        return true;
    }
    uint64_t tellg() override
    {
        long p = std::ftell(f_);
        return p < 0 ? 0 : static_cast<uint64_t>(p);
    }
    void seekg(uint64_t pos) override
    {
        if (pos > static_cast<uint64_t>(INT64_MAX) ||
            fseeko(f_, static_cast<off_t>(pos), SEEK_SET) != 0)
            throw std::runtime_error("seek failed");
    }
    void clear() override { std::clearerr(f_); }

  private:
    std::FILE *f_;
};

// Reads a NUL-terminated attribute or type name of at most max bytes.
bool read_name(CheckedIStream &in, char *buf, size_t max)
{
    for (size_t n = 0; n < max; n++) {
        in.read(buf + n, 1);
        if (buf[n] == '\0') return true;
    }
    return false;
}

// The bytes OpenEXR 3.1's reader of a standard attribute type consumes whatever the
// declared size says; 0 for the types it reads by their declared size (string,
// stringvector, idmanifest, chlist and preview: the last two are checked apart, unknown
// types are opaque).
size_t fixed_attribute_size(const char *type)
{
    static const struct {
        const char *type;
        size_t size;
    } fixed[] = {{"box2i", 16},
                 {"box2f", 16},
                 {"chromaticities", 32},
                 {"compression", 1},
                 {"deepImageState", 1},
                 {"double", 8},
                 {"envmap", 1},
                 {"float", 4},
                 {"int", 4},
                 {"keycode", 28},
                 {"lineOrder", 1},
                 {"m33f", 36},
                 {"m33d", 72},
                 {"m44f", 64},
                 {"m44d", 128},
                 {"rational", 8},
                 {"tiledesc", 9},
                 {"timecode", 8},
                 {"v2i", 8},
                 {"v2f", 8},
                 {"v2d", 16},
                 {"v3i", 12},
                 {"v3f", 12},
                 {"v3d", 24}};
    for (const auto &f : fixed)
        if (std::strcmp(type, f.type) == 0) return f.size;
    return 0;
}

// Whether a channel list of `size` bytes is exactly what OpenEXR's reader consumes:
// entries of a name (at most 255 characters and its NUL) and 16 bytes, then a NUL.
bool channel_list_fits(CheckedIStream &in, int32_t size, int64_t *channels)
{
    std::string bytes(static_cast<size_t>(size), '\0');
    if (size > 0) in.read(&bytes[0], size);
    size_t at = 0;
    for (*channels = 0;; ++*channels) {
        const size_t nul = bytes.find('\0', at);
        if (nul == std::string::npos || nul - at > 255) return false;
        if (nul == at) return nul + 1 == bytes.size(); // the list's terminator
        at = nul + 1 + 16;
        if (at > bytes.size()) return false;
    }
}

// Scan lines OpenEXR decodes as one block, by compression (OpenEXR's enum order).
int64_t lines_per_block(int compression)
{
    static const int lines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
    return compression >= 0 && compression < 10 ? lines[compression] : 256;
}

// Walks the attribute lists of the header(s) and checks every attribute's declared size
// against the bytes the file has and against what OpenEXR will read.  OpenEXR 3.1
// allocates an attribute's declared size before it reads it, so 29 bytes claiming 2 GiB
// would cost 2 GiB; here they are simply a truncated file.  And its readers of fixed-size
// types and of channel lists ignore the declared size: a size that disagrees would make
// this walk and OpenEXR's part ways, and OpenEXR then meet an unchecked size.
lumis_status check_attribute_sizes(CheckedIStream &in, const lumis__read_ctx *ctx)
{
    unsigned char head[8];
    in.read(reinterpret_cast<char *>(head), 8); // magic and version
    const uint32_t flags =
        head[4] | head[5] << 8 | head[6] << 16 | static_cast<uint32_t>(head[7]) << 24;
    const bool multipart = flags & 0x1000, long_names = flags & 0x400;
    const size_t max_name = long_names ? 256 : 32;
    for (;;) {
        char name[256], type[256];
        // What OpenEXR sizes its block buffers from when the file is opened.
        int64_t width = 0, channels = 0;
        int compression = 0;
        bool tiled = false;
        for (;;) {
            if (!read_name(in, name, max_name) || (name[0] && !read_name(in, type, max_name)))
                return fail(ctx->errors, LUMIS_ERR_BAD_HEADER,
                            "%s: header attribute name longer than %zu bytes", ctx->name, max_name);
            if (!name[0]) { // end of this header
                // A scan-line file's decoder holds a block of lines of every channel: a
                // tiny file claiming 3 million pixels a row under a 32-line compression
                // would cost OpenEXR gigabytes before a pixel is read.
                const int64_t block =
                    width * (channels > 0 ? channels : 1) * 4 * lines_per_block(compression);
                if (!tiled && block > (int64_t{256} << 20))
                    return fail(ctx->errors, LUMIS_ERR_TOO_LARGE,
                                "%s: rows of %lld pixels x %lld channels in blocks of %lld "
                                "lines need %lld MB to decode (limit 256 MB)",
                                ctx->name, static_cast<long long>(width),
                                static_cast<long long>(channels),
                                static_cast<long long>(lines_per_block(compression)),
                                static_cast<long long>(block >> 20));
                break;
            }
            unsigned char sz[4];
            in.read(reinterpret_cast<char *>(sz), 4);
            const int32_t size = static_cast<int32_t>(sz[0] | sz[1] << 8 | sz[2] << 16 |
                                                      static_cast<uint32_t>(sz[3]) << 24);
            const uint64_t left = in.size - in.tellg();
            if (size < 0)
                return fail(ctx->errors, LUMIS_ERR_BAD_HEADER,
                            "%s: attribute '%s' has a negative size", ctx->name, name);
            if (static_cast<uint64_t>(size) > left)
                return fail(ctx->errors, LUMIS_ERR_TRUNCATED,
                            "%s: attribute '%s' claims %d bytes, the file has %llu left", ctx->name,
                            name, size, static_cast<unsigned long long>(left));
            const uint64_t value_at = in.tellg();
            const size_t fixed = fixed_attribute_size(type);
            bool fits = true;
            if (fixed) {
                fits = static_cast<size_t>(size) == fixed;
            } else if (std::strcmp(type, "chlist") == 0) {
                fits = channel_list_fits(in, size, &channels);
            } else if (std::strcmp(type, "preview") == 0) { // width, height, then RGBA8
                unsigned char wh[8] = {0};
                if (size >= 8) in.read(reinterpret_cast<char *>(wh), 8);
                const uint64_t pw = wh[0] | wh[1] << 8 | wh[2] << 16 | uint64_t{wh[3]} << 24;
                const uint64_t ph = wh[4] | wh[5] << 8 | wh[6] << 16 | uint64_t{wh[7]} << 24;
                const uint64_t pixels = static_cast<uint64_t>(size - 8) / 4;
                fits = size >= 8 && size % 4 == 0 && pw < (1u << 31) && ph < (1u << 31) &&
                       pw * ph == pixels;
            } else if (std::strcmp(type, "floatvector") == 0) {
                fits = size % 4 == 0;
            }
            if (!fits)
                return fail(ctx->errors, LUMIS_ERR_BAD_HEADER,
                            "%s: attribute '%s' of type '%s' cannot have %d bytes", ctx->name, name,
                            type, size);
            // OpenEXR sizes its line or tile buffers from these when the file is opened,
            // before lumis sees the header: the pixel limit applies to them here.
            const bool window = !std::strcmp(name, "dataWindow") && !std::strcmp(type, "box2i");
            const bool tiles = !std::strcmp(name, "tiles") && !std::strcmp(type, "tiledesc");
            if (window || tiles) {
                unsigned char v[16];
                in.seekg(value_at);
                in.read(reinterpret_cast<char *>(v), window ? 16 : 8);
                int64_t x[4] = {0, 0, 0, 0};
                for (int k = 0; k < (window ? 4 : 2); k++)
                    x[k] = static_cast<int32_t>(v[4 * k] | v[4 * k + 1] << 8 | v[4 * k + 2] << 16 |
                                                static_cast<uint32_t>(v[4 * k + 3]) << 24);
                const int64_t w = window ? x[2] - x[0] + 1 : x[0];
                const int64_t h = window ? x[3] - x[1] + 1 : x[1];
                if (window) width = w;
                tiled |= tiles;
                const lumis_status st = lumis_image_check_size(w, h, ctx->max_pixels);
                if (st != LUMIS_OK)
                    return fail(ctx->errors, st, "%s: %s %lld x %lld: %s", ctx->name,
                                window ? "data window" : "tile size", static_cast<long long>(w),
                                static_cast<long long>(h), lumis_status_string(st));
            }
            if (!std::strcmp(name, "compression") && !std::strcmp(type, "compression") &&
                size == 1) {
                unsigned char c = 0;
                in.seekg(value_at);
                in.read(reinterpret_cast<char *>(&c), 1);
                compression = c;
            }
            in.seekg(value_at + static_cast<uint64_t>(size));
        }
        if (!multipart) return LUMIS_OK;
        // Multi-part: the list of headers ends with an empty header (a lone NUL).
        char next;
        in.read(&next, 1);
        if (next == '\0') return LUMIS_OK;
        in.seekg(in.tellg() - 1);
    }
}

// OpenEXR decodes blocks on its global thread pool.  A reader borrows the pool for the
// duration of one read: the first of concurrent readers grows it to the requested size
// (0 == one per core) and the last one restores what it was.  lumis thus leaves no threads
// behind, and a process may fork() between reads and writes (pool threads would not
// survive the fork, and OpenEXR's writer waits on them).
class DecodePool
{
  public:
    explicit DecodePool(int requested)
    {
        int n = requested > 0 ? requested : static_cast<int>(std::thread::hardware_concurrency());
        if (n <= 1) return;
        std::lock_guard<std::mutex> lock(mutex_);
        if (users_++ == 0) saved_ = Imf::globalThreadCount();
        if (Imf::globalThreadCount() < n) Imf::setGlobalThreadCount(n);
        threads_ = n;
    }
    ~DecodePool()
    {
        if (!threads_) return;
        std::lock_guard<std::mutex> lock(mutex_);
        if (--users_ == 0) Imf::setGlobalThreadCount(saved_);
    }
    DecodePool(const DecodePool &) = delete;
    DecodePool &operator=(const DecodePool &) = delete;
    int threads() const { return threads_; }

  private:
    int threads_ = 0; // 0: decode in the caller's thread
    static std::mutex mutex_;
    static int users_, saved_;
};
std::mutex DecodePool::mutex_;
int DecodePool::users_ = 0, DecodePool::saved_ = 0;

lumis_status read_stream(CheckedIStream &in, const lumis__read_ctx *ctx, lumis_image **out)
{
    const lumis_error_sink *err = ctx->errors;
    bool constructed = false;
    try {
        // Check the magic ourselves: OpenEXR's message for a non-EXR file is vague.
        char magic[4] = {0, 0, 0, 0};
        try {
            in.read(magic, 4);
        } catch (...) {
        }
        if (!Imf::isImfMagic(magic))
            return fail(err, LUMIS_ERR_BAD_MAGIC, "%s: not an OpenEXR file (bad magic number)",
                        ctx->name);
        in.seekg(0);
        in.hit_end = false;
        lumis_status checked = check_attribute_sizes(in, ctx);
        if (checked != LUMIS_OK) return checked;
        in.seekg(0);

        DecodePool pool(ctx->threads);
        Imf::InputFile file(in, pool.threads());
        constructed = true;
        const Imf::Header &hdr = file.header();
        const Imath::Box2i dw = hdr.dataWindow();
        const int64_t w = static_cast<int64_t>(dw.max.x) - dw.min.x + 1;
        const int64_t h = static_cast<int64_t>(dw.max.y) - dw.min.y + 1;
        lumis_status st = lumis_image_check_size(w, h, ctx->max_pixels);
        if (st != LUMIS_OK)
            return fail(err, st, "%s: data window %lld x %lld: %s", ctx->name,
                        static_cast<long long>(w), static_cast<long long>(h),
                        lumis_status_string(st));

        const Imf::ChannelList &ch = hdr.channels();
        const bool rgb = ch.findChannel("R") && ch.findChannel("G") && ch.findChannel("B");
        const bool grey = !rgb && ch.findChannel("Y");
        if (!rgb && !grey)
            return fail(err, LUMIS_ERR_MISSING_CHANNELS,
                        "%s: no R, G, B (or Y) channels in the first layer", ctx->name);
        for (const char *name : {"R", "G", "B", "Y"}) {
            const Imf::Channel *c = ch.findChannel(name);
            if (c && (c->xSampling != 1 || c->ySampling != 1))
                return fail(err, LUMIS_ERR_UNSUPPORTED, "%s: subsampled channel %s", ctx->name,
                            name);
        }
        ctx->info->had_alpha = ch.findChannel("A") != nullptr;
        ctx->info->grey = grey;

        st = lumis_image_create(static_cast<int>(w), static_cast<int>(h), out);
        if (st != LUMIS_OK) return fail(err, st, "%s: out of memory", ctx->name);
        // OpenEXR addresses pixel (x, y) at base + x * xs + y * ys with absolute data-window
        // coordinates; compute the shifted base as an integer to keep pointer arithmetic legal.
        const size_t xs = 3 * sizeof(float), ys = xs * static_cast<size_t>(w);
        const uintptr_t base = reinterpret_cast<uintptr_t>((*out)->pixels) -
                               static_cast<uintptr_t>(static_cast<intptr_t>(dw.min.x)) * xs -
                               static_cast<uintptr_t>(static_cast<intptr_t>(dw.min.y)) * ys;
        Imf::FrameBuffer fb;
        static const char *const names[3] = {"R", "G", "B"};
        // A grey file's Y goes to R and is copied to G and B below: a frame buffer holds one
        // slice per name (inserting Y three times kept only the last, blue).
        for (int c = 0; c < (grey ? 1 : 3); c++)
            fb.insert(
                grey ? "Y" : names[c],
                Imf::Slice(Imf::FLOAT, reinterpret_cast<char *>(base + c * sizeof(float)), xs, ys));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        if (grey) {
            float *px = (*out)->pixels;
            const size_t count = static_cast<size_t>(w) * static_cast<size_t>(h);
            for (size_t k = 0; k < count; k++) px[3 * k + 1] = px[3 * k + 2] = px[3 * k];
        }
        return LUMIS_OK;
    } catch (const std::bad_alloc &) {
        return fail(err, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", ctx->name);
    } catch (const std::exception &e) {
        // OpenEXR reads missing scanline chunks as an exception with the line number.
        if (in.hit_end)
            return fail(err, LUMIS_ERR_TRUNCATED, "%s: data ends early (%s)", ctx->name, e.what());
        return fail(err, constructed ? LUMIS_ERR_CORRUPT : LUMIS_ERR_BAD_HEADER, "%s: %s",
                    ctx->name, e.what());
    } catch (...) {
        return fail(err, LUMIS_ERR_CORRUPT, "%s: unknown OpenEXR error", ctx->name);
    }
}

} // namespace

extern "C" lumis_status lumis__exr_read(const unsigned char *data, size_t size,
                                        const lumis__read_ctx *ctx, lumis_image **out)
{
    *out = nullptr;
    lumis_status st;
    try {
        if (data) {
            MemoryIStream in(data, size, ctx->name);
            st = read_stream(in, ctx, out);
        } else {
            std::FILE *f = std::fopen(ctx->name, "rb");
            if (!f)
                return fail(ctx->errors, LUMIS_ERR_OPEN, "%s: %s", ctx->name, std::strerror(errno));
            {
                FileIStream in(f, ctx->name, size);
                st = read_stream(in, ctx, out);
            }
            std::fclose(f);
        }
    } catch (...) { // constructing a stream (it copies the name) can throw
        st = fail(ctx->errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", ctx->name);
    }
    if (st != LUMIS_OK) {
        lumis_image_destroy(*out);
        *out = nullptr;
    }
    return st;
}

namespace
{

// Our enum in the order of lumis_exr_compression.
const Imf::Compression compressions[LUMIS_EXR_COMPRESSION_COUNT] = {
    Imf::ZIP_COMPRESSION,  Imf::NO_COMPRESSION,    Imf::RLE_COMPRESSION, Imf::ZIPS_COMPRESSION,
    Imf::PIZ_COMPRESSION,  Imf::PXR24_COMPRESSION, Imf::B44_COMPRESSION, Imf::B44A_COMPRESSION,
    Imf::DWAA_COMPRESSION, Imf::DWAB_COMPRESSION};

// OpenEXR writes through our stream, so that every error (a full disk at the last flush
// included) reaches the atomic writer, which checks the stream when it closes it; OpenEXR
// writing by name lost the error of its own stream's close, and an empty file replaced the
// output with success.
class FileOStream final : public Imf::OStream
{
  public:
    FileOStream(FILE *f, const char *name) : Imf::OStream(name), f_(f) {}
    void write(const char c[], int n) override
    {
        if (n > 0 && fwrite(c, 1, static_cast<size_t>(n), f_) != static_cast<size_t>(n))
            throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
    }
    uint64_t tellp() override
    {
        const off_t at = ftello(f_);
        if (at < 0) throw std::runtime_error(std::string("tell failed: ") + std::strerror(errno));
        return static_cast<uint64_t>(at);
    }
    void seekp(uint64_t pos) override
    {
        if (fseeko(f_, static_cast<off_t>(pos), SEEK_SET) != 0)
            throw std::runtime_error(std::string("seek failed: ") + std::strerror(errno));
    }

  private:
    FILE *f_;
};

template <class File> void write_pixels(File &file, const Imf::FrameBuffer &fb, int height)
{
    file.setFrameBuffer(fb);
    if constexpr (std::is_same_v<File, Imf::TiledOutputFile>)
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    else
        file.writePixels(height);
}

} // namespace

extern "C" lumis_status lumis__exr_write(FILE *out, const char *display_name,
                                         const lumis_image *image,
                                         const lumis_write_options *options)
{
    const lumis_error_sink *errors = &options->errors;
    const bool half = options->exr_half != 0;
    Imath::half *halves = nullptr;
    try {
        Imf::Header hdr(image->width, image->height);
        hdr.compression() = compressions[options->exr_compression];
        const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
        static const char *const names[3] = {"R", "G", "B"};
        for (const char *n : names) hdr.channels().insert(n, Imf::Channel(type));
        if (options->exr_tile_size > 0)
            hdr.setTileDescription(Imf::TileDescription(
                static_cast<unsigned>(options->exr_tile_size),
                static_cast<unsigned>(options->exr_tile_size), Imf::ONE_LEVEL));
        Imf::FrameBuffer fb;
        const size_t n = static_cast<size_t>(image->width) * static_cast<size_t>(image->height) * 3;
        if (half) {
            // Half overflows to infinity above 65504 (a sun disk easily does): clamp instead;
            // NaN is written as 0, as the HDR writer does (the clamp alone made it 65504, the
            // brightest half).  Converting here also serves tiled files, which do not convert
            // pixel types.
            halves = new Imath::half[n];
            for (size_t k = 0; k < n; k++) {
                const float v = image->pixels[k];
                halves[k] = Imath::half(v < 65504.0f ? v : std::isnan(v) ? 0.0f : 65504.0f);
            }
        }
        const size_t elem = half ? sizeof(Imath::half) : sizeof(float);
        const size_t xs = 3 * elem, ys = xs * static_cast<size_t>(image->width);
        char *base =
            half ? reinterpret_cast<char *>(halves) : reinterpret_cast<char *>(image->pixels);
        for (int c = 0; c < 3; c++)
            fb.insert(names[c], Imf::Slice(type, base + static_cast<size_t>(c) * elem, xs, ys));
        // Written in the caller's thread (0): writing is rare and needs no pool.
        if (options->exr_tile_size > 0) {
            FileOStream os(out, display_name);
            Imf::TiledOutputFile file(os, hdr, 0);
            write_pixels(file, fb, image->height);
        } else {
            FileOStream os(out, display_name);
            Imf::OutputFile file(os, hdr, 0);
            write_pixels(file, fb, image->height);
        }
        delete[] halves;
        return LUMIS_OK;
    } catch (const std::exception &e) {
        delete[] halves;
        return fail(errors, LUMIS_ERR_WRITE, "%s: %s", display_name, e.what());
    } catch (...) {
        delete[] halves;
        return fail(errors, LUMIS_ERR_WRITE, "%s: unknown OpenEXR error", display_name);
    }
}
