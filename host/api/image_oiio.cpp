// The OpenImageIO shim: the only C++ in lanecast. Writes one image and turns
// every failure or exception into a message; nothing crosses this boundary
// but C types.
#include <OpenImageIO/imageio.h>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <string>

extern "C" int lci_oiio_write(const char *path, int width, int height, int channels, int is_float,
                              const void *pixels, char *err, size_t errlen);
extern "C" int lci_oiio_can_write(const char *path);

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

extern "C" int lci_oiio_write(const char *path, int width, int height, int channels, int is_float,
                              const void *pixels, char *err, size_t errlen)
{
    try {
        auto out = OIIO::ImageOutput::create(path);
        if (!out) {
            std::string e = OIIO::geterror();
            return fail(err, errlen, "no image writer for this file name" + (e.empty() ? "" : ": " + e));
        }
        OIIO::TypeDesc type = is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
        OIIO::ImageSpec spec(width, height, channels, type);
        if (channels == 4) spec.alpha_channel = 3;
        spec.attribute("Software", "lanecast");
        if (!out->open(path, spec)) return fail(err, errlen, out->geterror());
        if (!out->write_image(type, pixels)) {
            std::string e = out->geterror();
            out->close();
            return fail(err, errlen, e);
        }
        if (!out->close()) return fail(err, errlen, out->geterror());
        return 0;
    } catch (const std::exception &e) {
        return fail(err, errlen, std::string("OpenImageIO: ") + e.what());
    } catch (...) {
        return fail(err, errlen, "OpenImageIO: unknown exception");
    }
}
