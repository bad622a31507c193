// The GDCM shim: the only GDCM calls in lanecast (the DICOM reader's logic
// is in dicom.c). Reads a file's header up to its pixel data and decodes its
// pixel data; every failure or exception becomes a message, and nothing but
// C types crosses this boundary (as host/api/image_oiio.cpp does for
// OpenImageIO). Element values are parsed here from their bytes rather than
// through gdcm::Attribute, whose conversions trust an element's length.
#include <gdcmByteValue.h>
#include <gdcmDataElement.h>
#include <gdcmDataSet.h>
#include <gdcmFile.h>
#include <gdcmFileMetaInformation.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmReader.h>
#include <gdcmSequenceOfItems.h>
#include <gdcmTag.h>
#include <gdcmTrace.h>
#include <gdcmTransferSyntax.h>
#include <gdcmUIDs.h>
#include <gdcmVersion.h>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <set>
#include <string>
#include <vector>
#include "host/formats/dicom_gdcm.h"

namespace {

struct bad_element : std::exception {
    std::string msg;
    explicit bad_element(std::string m) : msg(std::move(m)) {}
    const char *what() const noexcept override { return msg.c_str(); }
};

int fail(char *err, size_t errlen, const std::string &msg)
{
    std::snprintf(err, errlen, "%s", msg.c_str());
    return -1;
}

// GDCM prints its warnings and errors to stderr; lanecast reports its own.
void quiet()
{
    gdcm::Trace::SetDebug(false);
    gdcm::Trace::SetWarning(false);
    gdcm::Trace::SetError(false);
}

std::string tag_name(const gdcm::Tag &t, const char *name)
{
    char b[96];
    std::snprintf(b, sizeof b, "(%04X,%04X) %s", t.GetGroup(), t.GetElement(), name);
    return b;
}

// The element's bytes; NULL when it is absent or empty.
const gdcm::ByteValue *bytes_of(const gdcm::DataSet &ds, const gdcm::Tag &t)
{
    if (!ds.FindDataElement(t)) return nullptr;
    const gdcm::DataElement &de = ds.GetDataElement(t);
    if (de.IsEmpty()) return nullptr;
    const gdcm::ByteValue *bv = de.GetByteValue();
    return bv && bv->GetLength() > 0 ? bv : nullptr;
}

// A text value without its padding (trailing spaces and NULs, leading spaces).
bool text(const gdcm::DataSet &ds, const gdcm::Tag &t, std::string &out)
{
    const gdcm::ByteValue *bv = bytes_of(ds, t);
    if (!bv) return false;
    out.assign(bv->GetPointer(), bv->GetLength());
    size_t e = out.find_last_not_of(std::string(" \0", 2));
    size_t b = out.find_first_not_of(' ');
    out = e == std::string::npos || b == std::string::npos ? std::string() : out.substr(b, e - b + 1);
    return !out.empty();
}

void copy(char *dst, size_t n, const std::string &s) { std::snprintf(dst, n, "%s", s.c_str()); }

// n decimal strings (DS, IS) separated by backslashes; absent: false.
bool numbers(const gdcm::DataSet &ds, const gdcm::Tag &t, const char *name, double *out, int n)
{
    std::string s;
    if (!text(ds, t, s)) return false;
    const char *p = s.c_str();
    for (int i = 0; i < n; i++) {
        char *end;
        errno = 0;
        double v = std::strtod(p, &end);
        if (end == p || errno || !std::isfinite(v))
            throw bad_element(tag_name(t, name) + " is '" + s + "', expected " + std::to_string(n) + " number" +
                              (n > 1 ? "s" : ""));
        out[i] = v;
        p = end;
        while (*p == ' ') p++;
        if (i + 1 < n) {
            if (*p != '\\')
                throw bad_element(tag_name(t, name) + " is '" + s + "', expected " + std::to_string(n) + " numbers");
            p++;
        }
    }
    return true;
}

// An unsigned short (US), little-endian as GDCM holds it; absent: false.
bool ushort(const gdcm::DataSet &ds, const gdcm::Tag &t, const char *name, int &out)
{
    const gdcm::ByteValue *bv = bytes_of(ds, t);
    if (!bv) return false;
    if (bv->GetLength() != 2)
        throw bad_element(tag_name(t, name) + " holds " + std::to_string(bv->GetLength()) + " bytes, expected 2");
    const unsigned char *b = reinterpret_cast<const unsigned char *>(bv->GetPointer());
    out = b[0] | b[1] << 8;
    return true;
}

// Item `i` (1-based) of sequence t's nested data set, or NULL.
const gdcm::DataSet *item(const gdcm::DataSet &ds, const gdcm::Tag &t, size_t i, gdcm::SmartPointer<gdcm::SequenceOfItems> &keep)
{
    if (!ds.FindDataElement(t)) return nullptr;
    keep = ds.GetDataElement(t).GetValueAsSQ();
    if (!keep || keep->GetNumberOfItems() < i) return nullptr;
    return &keep->GetItem(i).GetNestedDataSet();
}

const gdcm::Tag IPP(0x0020, 0x0032), IOP(0x0020, 0x0037), SPACING(0x0028, 0x0030), SLOPE(0x0028, 0x1053),
    INTERCEPT(0x0028, 0x1052), BETWEEN(0x0018, 0x0088), THICKNESS(0x0018, 0x0050);
const gdcm::Tag SHARED_FG(0x5200, 0x9229), PER_FRAME_FG(0x5200, 0x9230), PLANE_POSITION(0x0020, 0x9113),
    PLANE_ORIENTATION(0x0020, 0x9116), PIXEL_MEASURES(0x0028, 0x9110), VALUE_TRANSFORM(0x0028, 0x9145);

// Rescale Slope and Intercept of one data set (0028,1053), (0028,1052):
// false when it has neither; a zero slope fails, naming `where`.
bool rescale(const gdcm::DataSet &ds, double *slope, double *intercept, const std::string &where)
{
    double s = 1.0, b = 0.0;
    int hs = numbers(ds, SLOPE, "Rescale Slope", &s, 1), hb = numbers(ds, INTERCEPT, "Rescale Intercept", &b, 1);
    if (!hs && !hb) return false;
    if (s == 0.0) throw bad_element(tag_name(SLOPE, "Rescale Slope") + " is 0" + where);
    *slope = s, *intercept = b;
    return true;
}

// The geometry and rescale elements of one data set (the top level, or a
// functional group's macros), each only where m lacks it yet.
void geometry(const gdcm::DataSet &ds, lci_dcm_meta *m)
{
    if (!m->have_iop) m->have_iop = numbers(ds, IOP, "Image Orientation (Patient)", m->iop, 6);
    if (!m->have_spacing) m->have_spacing = numbers(ds, SPACING, "Pixel Spacing", m->spacing, 2);
    if (!m->have_between) m->have_between = numbers(ds, BETWEEN, "Spacing Between Slices", &m->between, 1);
    if (!m->have_thickness) m->have_thickness = numbers(ds, THICKNESS, "Slice Thickness", &m->thickness, 1);
    if (!m->have_rescale) m->have_rescale = rescale(ds, &m->slope, &m->intercept, "");
}

// A copy of v in malloc'd memory (the C side frees it).
double *c_copy(const std::vector<double> &v)
{
    double *p = static_cast<double *>(std::malloc(sizeof(double) * v.size()));
    if (!p) throw std::bad_alloc();
    std::memcpy(p, v.data(), sizeof(double) * v.size());
    return p;
}

// Enhanced multi-frame files (CT, MR, PET): the shared functional groups,
// then the first frame's, for the geometry; every frame's plane position
// and Pixel Value Transformation (rescale), which may differ per frame
// (PS3.3 C.7.6.16.2.9: a macro is shared or given per frame).
void functional_groups(const gdcm::DataSet &ds, lci_dcm_meta *m)
{
    gdcm::SmartPointer<gdcm::SequenceOfItems> k1, k2;
    const gdcm::Tag macros[] = {PIXEL_MEASURES, PLANE_ORIENTATION, VALUE_TRANSFORM, PLANE_POSITION};
    for (const gdcm::Tag &g : {SHARED_FG, PER_FRAME_FG}) {
        const gdcm::DataSet *fg = item(ds, g, 1, k1);
        for (int i = 0; fg && i < 4; i++)
            if (const gdcm::DataSet *mac = item(*fg, macros[i], 1, k2)) geometry(*mac, m);
    }
    if (!ds.FindDataElement(PER_FRAME_FG)) return;
    gdcm::SmartPointer<gdcm::SequenceOfItems> sq = ds.GetDataElement(PER_FRAME_FG).GetValueAsSQ();
    if (!sq) throw bad_element(tag_name(PER_FRAME_FG, "Per-frame Functional Groups Sequence") + " is not a sequence");
    size_t n = sq->GetNumberOfItems();
    if (n == 0) return;
    if (n != static_cast<size_t>(m->frames))
        throw bad_element(tag_name(PER_FRAME_FG, "Per-frame Functional Groups Sequence") + " has " + std::to_string(n) +
                          " items for " + std::to_string(m->frames) + " frames");
    std::vector<double> pos(3 * n), scale(2 * n);
    size_t have = 0, scaled = 0;
    for (size_t f = 0; f < n; f++) {
        const gdcm::DataSet &fds = sq->GetItem(f + 1).GetNestedDataSet();
        const gdcm::DataSet *pp = item(fds, PLANE_POSITION, 1, k2);
        if (pp && numbers(*pp, IPP, "Image Position (Patient)", &pos[3 * f], 3)) have++;
        const gdcm::DataSet *vt = item(fds, VALUE_TRANSFORM, 1, k2);
        if (vt && rescale(*vt, &scale[2 * f], &scale[2 * f + 1], " in frame " + std::to_string(f) + "'s " +
                                                                    tag_name(VALUE_TRANSFORM, "Pixel Value Transformation Sequence")))
            scaled++;
    }
    if (have != 0 && have != n)
        throw bad_element(tag_name(PLANE_POSITION, "Plane Position Sequence") + " gives positions for " +
                          std::to_string(have) + " of " + std::to_string(n) + " frames");
    if (scaled != 0 && scaled != n)
        throw bad_element(tag_name(VALUE_TRANSFORM, "Pixel Value Transformation Sequence") + " gives a rescale for " +
                          std::to_string(scaled) + " of " + std::to_string(n) + " frames");
    if (have) {
        m->frame_ipp = c_copy(pos);
        if (!m->have_ipp) std::memcpy(m->ipp, m->frame_ipp, sizeof m->ipp), m->have_ipp = 1;
    }
    if (scaled) {
        m->frame_rescale = c_copy(scale);
        m->have_rescale = 1, m->slope = scale[0], m->intercept = scale[1];
    }
}

// Decoders GDCM 3.0 has: everything it names but video and JPIP references.
bool decodable(gdcm::TransferSyntax::TSType t)
{
    switch (t) {
    case gdcm::TransferSyntax::MPEG2MainProfile:
    case gdcm::TransferSyntax::MPEG2MainProfileHighLevel:
    case gdcm::TransferSyntax::MPEG4AVCH264HighProfileLevel4_1:
    case gdcm::TransferSyntax::MPEG4AVCH264BDcompatibleHighProfileLevel4_1:
    case gdcm::TransferSyntax::JPIPReferenced:
    case gdcm::TransferSyntax::TS_END: return false;
    default: return true;
    }
}

void header(const char *path, lci_dcm_meta *m)
{
    gdcm::Reader r;
    r.SetFileName(path);
    std::set<gdcm::Tag> skip;
    skip.insert(gdcm::Tag(0x7fe0, 0x0010));
    if (!r.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010), skip))
        throw bad_element("GDCM cannot parse it as DICOM (not a DICOM file, or damaged before its pixel data)");
    const gdcm::File &file = r.GetFile();
    const gdcm::FileMetaInformation &fmi = file.GetHeader();
    const gdcm::DataSet &ds = file.GetDataSet();
    std::string s;
    if (text(fmi, gdcm::Tag(0x0002, 0x0010), s)) copy(m->ts_uid, sizeof m->ts_uid, s);
    gdcm::TransferSyntax::TSType tt =
        m->ts_uid[0] ? gdcm::TransferSyntax::GetTSType(m->ts_uid) : fmi.GetDataSetTransferSyntax().GetNegociatedType() ==
                                                                          gdcm::TransferSyntax::Implicit
                                                                      ? gdcm::TransferSyntax::ImplicitVRLittleEndian
                                                                      : gdcm::TransferSyntax::ExplicitVRLittleEndian;
    m->ts_known = decodable(tt);
    m->encapsulated = fmi.GetDataSetTransferSyntax().IsEncapsulated();
    if (m->ts_uid[0]) {
        gdcm::UIDs uid;
        if (uid.SetFromUID(m->ts_uid) && uid.GetName()) copy(m->ts_name, sizeof m->ts_name, uid.GetName());
    }
    if (text(ds, gdcm::Tag(0x0020, 0x000e), s)) copy(m->series_uid, sizeof m->series_uid, s);
    if (text(ds, gdcm::Tag(0x0008, 0x0060), s)) copy(m->modality, sizeof m->modality, s);
    if (text(ds, gdcm::Tag(0x0008, 0x103e), s)) copy(m->description, sizeof m->description, s);
    if (text(ds, gdcm::Tag(0x0028, 0x0004), s)) copy(m->photometric, sizeof m->photometric, s);
    ushort(ds, gdcm::Tag(0x0028, 0x0010), "Rows", m->rows);
    ushort(ds, gdcm::Tag(0x0028, 0x0011), "Columns", m->cols);
    ushort(ds, gdcm::Tag(0x0028, 0x0100), "Bits Allocated", m->bits_allocated);
    ushort(ds, gdcm::Tag(0x0028, 0x0101), "Bits Stored", m->bits_stored);
    ushort(ds, gdcm::Tag(0x0028, 0x0102), "High Bit", m->high_bit);
    ushort(ds, gdcm::Tag(0x0028, 0x0103), "Pixel Representation", m->pixel_rep);
    m->samples = 1;
    ushort(ds, gdcm::Tag(0x0028, 0x0002), "Samples per Pixel", m->samples);
    double v;
    m->frames = 1;
    if (numbers(ds, gdcm::Tag(0x0028, 0x0008), "Number of Frames", &v, 1)) {
        if (!(v >= 1 && v <= 1e6 && v == std::floor(v)))
            throw bad_element(tag_name(gdcm::Tag(0x0028, 0x0008), "Number of Frames") + " is " + std::to_string(v) +
                              ", expected 1 to 1000000");
        m->frames = static_cast<int>(v);
    }
    if (numbers(ds, gdcm::Tag(0x0020, 0x0013), "Instance Number", &v, 1) && std::fabs(v) < 2e9)
        m->instance = static_cast<int>(v);
    m->slope = 1.0, m->intercept = 0.0;
    m->have_ipp = numbers(ds, IPP, "Image Position (Patient)", m->ipp, 3);
    geometry(ds, m);
    functional_groups(ds, m);
    if (m->frames > 1 && !m->frame_ipp && ds.FindDataElement(gdcm::Tag(0x3004, 0x000c))) {
        std::string g;
        text(ds, gdcm::Tag(0x3004, 0x000c), g);
        m->frame_offset = static_cast<double *>(std::calloc(static_cast<size_t>(m->frames), sizeof(double)));
        if (!m->frame_offset) throw std::bad_alloc();
        if (!numbers(ds, gdcm::Tag(0x3004, 0x000c), "Grid Frame Offset Vector", m->frame_offset, m->frames))
            std::free(m->frame_offset), m->frame_offset = nullptr;
    }
}

void drop(lci_dcm_meta *m)
{
    std::free(m->frame_ipp), std::free(m->frame_offset), std::free(m->frame_rescale);
    m->frame_ipp = m->frame_offset = m->frame_rescale = nullptr;
}

} // namespace

extern "C" int lci_gdcm_header(const char *path, lci_dcm_meta *m, char *err, size_t errlen)
{
    std::memset(m, 0, sizeof *m);
    try {
        quiet();
        header(path, m);
        return 0;
    } catch (const bad_element &e) {
        drop(m);
        return fail(err, errlen, e.msg);
    } catch (const std::exception &e) {
        drop(m);
        return fail(err, errlen, std::string("GDCM: ") + e.what());
    } catch (...) {
        drop(m);
        return fail(err, errlen, "GDCM: unknown exception");
    }
}

extern "C" int lci_gdcm_pixels(const char *path, void *dst, size_t bytes, char *err, size_t errlen)
{
    try {
        quiet();
        gdcm::ImageReader r;
        r.SetFileName(path);
        if (!r.Read()) return fail(err, errlen, "GDCM cannot read the image (damaged or truncated pixel data?)");
        const gdcm::Image &img = r.GetImage();
        unsigned long n = img.GetBufferLength();
        if (n != bytes)
            return fail(err, errlen, "GDCM's image holds " + std::to_string(n) + " bytes, the header's sizes give " +
                                         std::to_string(bytes));
        if (!img.GetBuffer(static_cast<char *>(dst)))
            return fail(err, errlen, "GDCM could not decode the pixel data (damaged or truncated?)");
        return 0;
    } catch (const std::exception &e) {
        return fail(err, errlen, std::string("GDCM: ") + e.what());
    } catch (...) {
        return fail(err, errlen, "GDCM: unknown exception");
    }
}

extern "C" const char *lci_gdcm_version(void) { return gdcm::Version::GetVersion(); }
