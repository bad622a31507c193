// Compares two image files (any format OpenImageIO reads) through the tests'
// one comparer (imgcmp.c): `view_imgcmp GOT WANT exact` passes when every
// decoded value is equal, `view_imgcmp GOT WANT PSNR` when the PSNR is at
// least PSNR dB (any per-channel difference), `view_imgcmp GOT WANT max=D` when
// no decoded value differs by more than D/255 (D in 8-bit steps). Exit 0 pass, 1 fail, 2 unreadable.
#include <OpenImageIO/imageio.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>
extern "C" {
#include "imgcmp.h"
}

static bool load(const char *path, std::vector<float> &rgba, int &w, int &h)
{
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::fprintf(stderr, "view_imgcmp: cannot read %s: %s\n", path, OIIO::geterror().c_str());
        return false;
    }
    const OIIO::ImageSpec &s = in->spec();
    w = s.width, h = s.height;
    int nc = s.nchannels;
    std::vector<float> px((size_t)w * h * nc);
    if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, px.data())) {
        std::fprintf(stderr, "view_imgcmp: cannot decode %s: %s\n", path, in->geterror().c_str());
        return false;
    }
    rgba.assign((size_t)w * h * 4, 1.0f);
    for (size_t i = 0; i < (size_t)w * h; i++)
        for (int c = 0; c < 4 && c < nc; c++) rgba[4 * i + c] = px[i * nc + c];
    return true;
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        std::fprintf(stderr, "usage: view_imgcmp GOT WANT exact|MIN_PSNR_DB\n");
        return 2;
    }
    std::vector<float> a, b;
    int wa, ha, wb, hb;
    if (!load(argv[1], a, wa, ha) || !load(argv[2], b, wb, hb)) return 2;
    if (wa != wb || ha != hb) {
        std::printf("imgcmp %s: FAIL sizes %dx%d and %dx%d\n", argv[1], wa, ha, wb, hb);
        return 1;
    }
    bool exact = !std::strcmp(argv[3], "exact"), bound = !std::strncmp(argv[3], "max=", 4);
    double psnr = exact || bound ? IMGCMP_NO_PSNR_BOUND : std::atof(argv[3]);
    double maxd = exact ? 0.0 : IMGCMP_NO_MAX_BOUND;
    if (exact) maxd = 1e-300; // any difference at all fails (0 would mean the default)
    if (bound) maxd = std::atof(argv[3] + 4) > 0.0 ? std::atof(argv[3] + 4) : 1e-300;
    return imgcmp_check(argv[1], a.data(), b.data(), wa, ha, maxd, psnr, nullptr) == 0 ? 0 : 1;
}
