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
    explicit CheckedIStream(const char *name) : Imf::IStream(name) {}
    bool hit_end = false;
};

class MemoryIStream final : public CheckedIStream
{
  public:
    MemoryIStream(const unsigned char *data, size_t size, const char *name)
        : CheckedIStream(name), data_(data), size_(size)
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
    FileIStream(std::FILE *f, const char *name) : CheckedIStream(name), f_(f) {}
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

        Imf::InputFile file(in, Imf::globalThreadCount());
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
        for (int c = 0; c < 3; c++)
            fb.insert(
                grey ? "Y" : names[c],
                Imf::Slice(Imf::FLOAT, reinterpret_cast<char *>(base + c * sizeof(float)), xs, ys));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
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
                FileIStream in(f, ctx->name);
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

template <class File> void write_pixels(File &file, const Imf::FrameBuffer &fb, int height)
{
    file.setFrameBuffer(fb);
    if constexpr (std::is_same_v<File, Imf::TiledOutputFile>)
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    else
        file.writePixels(height);
}

} // namespace

extern "C" lumis_status lumis__exr_write(const char *path, const char *display_name,
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
            // Half overflows to infinity above 65504 (a sun disk easily does): clamp instead.
            // Converting here also serves tiled files, which do not convert pixel types.
            halves = new Imath::half[n];
            for (size_t k = 0; k < n; k++)
                halves[k] = Imath::half(image->pixels[k] < 65504.0f ? image->pixels[k] : 65504.0f);
        }
        const size_t elem = half ? sizeof(Imath::half) : sizeof(float);
        const size_t xs = 3 * elem, ys = xs * static_cast<size_t>(image->width);
        char *base =
            half ? reinterpret_cast<char *>(halves) : reinterpret_cast<char *>(image->pixels);
        for (int c = 0; c < 3; c++)
            fb.insert(names[c], Imf::Slice(type, base + static_cast<size_t>(c) * elem, xs, ys));
        if (options->exr_tile_size > 0) {
            Imf::TiledOutputFile file(path, hdr, Imf::globalThreadCount());
            write_pixels(file, fb, image->height);
        } else {
            Imf::OutputFile file(path, hdr, Imf::globalThreadCount());
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
