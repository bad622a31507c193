/* Checked opens and allocations for the readers (checked.h). */
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "host/formats/checked.h"

static const char *kind_of_file(mode_t m)
{
    if (S_ISDIR(m)) return "a directory";
    if (S_ISFIFO(m)) return "a FIFO (named pipe)";
    if (S_ISCHR(m) || S_ISBLK(m)) return "a device";
    if (S_ISSOCK(m)) return "a socket";
    return "not a regular file";
}

lc_status lci_open_regular(lc_device *dev, const char *path, const char *owner, FILE **out, int64_t *size)
{
    *out = NULL;
    char who[1200];
    if (owner && strcmp(owner, path)) snprintf(who, sizeof who, "%s: its data file %s", owner, path);
    else snprintf(who, sizeof who, "%s", path);
    /* O_NONBLOCK: opening a FIFO with no writer would otherwise wait forever */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", who, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return lci_error(dev, LC_ERROR_IO, "%s: cannot stat: %s", who, strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return lci_error(dev, LC_ERROR_IO, "%s: is %s, not a regular file", who, kind_of_file(st.st_mode));
    }
    int fl = fcntl(fd, F_GETFL);
    if (fl >= 0) fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        int e = errno;
        close(fd);
        return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", who, strerror(e));
    }
    *out = f;
    if (size) *size = (int64_t)st.st_size;
    return LC_OK;
}

uint64_t lci_memory_limit(const lc_device *dev)
{
    if (dev && dev->load_max_memory) return (uint64_t)dev->load_max_memory;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return UINT64_MAX;
    return (uint64_t)pages / 4 * 3 * (uint64_t)page;
}

int lci_parse_memory(const char *s, uint64_t *out)
{
    if (!s || !isdigit((unsigned char)*s)) return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno || !isfinite(v) || v <= 0) return -1;
    double mul = 1;
    switch (toupper((unsigned char)*end)) {
    case 'K': mul = 1024.0, end++; break;
    case 'M': mul = 1024.0 * 1024, end++; break;
    case 'G': mul = 1024.0 * 1024 * 1024, end++; break;
    case 'T': mul = 1024.0 * 1024 * 1024 * 1024, end++; break;
    default: break;
    }
    if (mul > 1 && (end[0] == 'i' || end[0] == 'I') && (end[1] == 'B' || end[1] == 'b')) end += 2;
    else if (*end == 'B' || *end == 'b') end++;
    if (*end) return -1;
    double b = floor(v * mul);
    if (b < 1 || b >= 18446744073709551615.0) return -1;
    *out = (uint64_t)b;
    return 0;
}

/* bytes as "N bytes (X.Y GiB)" */
static const char *human(uint64_t b, char *buf, size_t n)
{
    static const char *const unit[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double x = (double)b;
    int u = -1;
    while (x >= 1024.0 && u < 5) x /= 1024.0, u++;
    if (u < 0) snprintf(buf, n, "%llu bytes", (unsigned long long)b);
    else snprintf(buf, n, "%llu bytes (%.1f %s)", (unsigned long long)b, x, unit[u]);
    return buf;
}

lc_status lci_size_check(lc_device *dev, const char *file, uint64_t count, uint64_t elem, uint64_t extra,
                         const char *what, uint64_t *bytes)
{
    *bytes = 0;
    if (elem && count > (UINT64_MAX - extra) / elem)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: %llu %s of %llu bytes overflow a 64-bit size", file,
                         (unsigned long long)count, what, (unsigned long long)elem);
    uint64_t b = count * elem + extra, lim = lci_memory_limit(dev);
    char need[64], allow[64];
    if (b > lim || b > (uint64_t)SIZE_MAX - 64)
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY,
                         "%s: %llu %s need %s, more than the memory limit of %s (%s; raise it with the load option "
                         "max_memory or --max-memory)",
                         file, (unsigned long long)count, what, human(b, need, sizeof need), human(lim, allow, sizeof allow),
                         dev && dev->load_max_memory ? "as set" : "3/4 of the physical memory");
    *bytes = b;
    return LC_OK;
}

void *lci_alloc_checked(lc_device *dev, const char *file, uint64_t count, uint64_t elem, uint64_t extra,
                        const char *what, int zero)
{
    uint64_t b;
    if (lci_size_check(dev, file, count, elem, extra, what, &b) != LC_OK) return NULL;
    void *p = zero ? calloc(b ? (size_t)b : 1, 1) : malloc(b ? (size_t)b : 1);
    char need[64];
    if (!p)
        lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu %s (%s)", file, (unsigned long long)count,
                  what, human(b, need, sizeof need));
    return p;
}
