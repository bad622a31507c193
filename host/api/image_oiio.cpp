// The OpenImageIO shim: the only C++ in lanecast, built as the module
// lanecast_oiio.so that host/api/image.c loads on the first image write. Encodes one image and turns
// every failure or exception into a message; nothing crosses this boundary
// but C types. Where the format's writer supports an I/O proxy the file is
// encoded into memory and the C side writes the bytes itself (checked writes
// and fsync: OpenImageIO's PNG and BMP writers do not report a full disk);
// otherwise OpenImageIO writes the (already created, private) temporary file.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

// The module's two entry points (host/api/image.c loads it with dlopen).
#define LCI_OIIO_API extern "C" __attribute__((visibility("default")))
LCI_OIIO_API int lci_oiio_encode(const char *path, const char *format_name, int width, int height, int channels,
                                 int is_float, const void *pixels, void **bytes, size_t *nbytes, char *err,
                                 size_t errlen);
LCI_OIIO_API int lci_oiio_can_write(const char *path);

static int fail(char *err, size_t errlen, const std::string &msg)
{
    std::snprintf(err, errlen, "%s", msg.c_str());
    return -1;
}

extern "C" int lci_oiio_can_write(const char *path)
{
    try {
        auto out = OIIO::ImageOutput::create(path);
        return out ? 1 : 0;
    } catch (...) {
        return 0;
    }
}

// Writes the image as format_name's file type (the writer is chosen from
// format_name, e.g. the final file name, the data go to path or memory).
// Returns 0 and, when the writer took a memory proxy, *bytes (malloc'd) and
// *nbytes; with *bytes == NULL the file at path was written directly.
extern "C" int lci_oiio_encode(const char *path, const char *format_name, int width, int height, int channels,
                               int is_float, const void *pixels, void **bytes, size_t *nbytes, char *err,
                               size_t errlen)
{
    *bytes = nullptr;
    *nbytes = 0;
    try {
        auto out = OIIO::ImageOutput::create(format_name);
        if (!out) {
            std::string e = OIIO::geterror();
            return fail(err, errlen, "no image writer for this file name" + (e.empty() ? "" : ": " + e));
        }
        OIIO::TypeDesc type = is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
        OIIO::ImageSpec spec(width, height, channels, type);
        if (channels == 4) spec.alpha_channel = 3;
        spec.attribute("Software", "lanecast");
        std::unique_ptr<OIIO::Filesystem::IOVecOutput> mem;
        if (out->supports("ioproxy")) {
            mem.reset(new OIIO::Filesystem::IOVecOutput());
            if (!out->set_ioproxy(mem.get())) mem.reset();
        }
        if (!out->open(mem ? std::string(format_name) : std::string(path), spec))
            return fail(err, errlen, out->geterror());
        if (!out->write_image(type, pixels)) {
            std::string e = out->geterror();
            out->close();
            return fail(err, errlen, e);
        }
        if (!out->close()) return fail(err, errlen, out->geterror());
        if (mem) {
            const std::vector<unsigned char> &b = mem->buffer();
            if (b.empty()) return fail(err, errlen, "the image encoder produced no bytes");
            *bytes = std::malloc(b.size());
            if (!*bytes) return fail(err, errlen, "out of memory for the encoded image");
            std::memcpy(*bytes, b.data(), b.size());
            *nbytes = b.size();
        }
        return 0;
    } catch (const std::exception &e) {
        return fail(err, errlen, std::string("OpenImageIO: ") + e.what());
    } catch (...) {
        return fail(err, errlen, "OpenImageIO: unknown exception");
    }
}
