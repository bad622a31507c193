/* The optional features of this build (meson features, lc_config.h) and
 * the one message for asking for one that is compiled out. */
#include <stdio.h>
#include <string.h>
#include "host/internal.h"

static const lc_feature_info features[] = {
    [LCI_FEATURE_ZLIB] = {"zlib", "zlib", LC_HAVE_ZLIB, "zlib1g-dev",
                          "gzip-compressed inputs: .gz particle files, NRRD gzip encoding, MetaImage compressed data"},
    [LCI_FEATURE_JSON] = {"json", "json-c", LC_HAVE_JSON, "libjson-c-dev",
                          "JSON transfer functions (SPEC.md): lc_tf_load, lc_tf_parse, --tf FILE.json"},
    [LCI_FEATURE_LAPACKE] = {"lapacke", "LAPACKE", LC_HAVE_LAPACKE, "liblapacke-dev",
                             "RBF encoding (least squares): lc_rbf_encode, lanecast encode"},
    [LCI_FEATURE_NIFTI] = {"nifti", "nifti_clib (libnifti2)", LC_HAVE_NIFTI, "libnifti2-dev",
                           "NIfTI-1/2 volumes: .nii, .nii.gz, .hdr/.img pairs"},
    [LCI_FEATURE_HDF5] = {"hdf5", "libhdf5", LC_HAVE_HDF5, "libhdf5-dev",
                          "HDF5 files: GADGET/AREPO/SWIFT PartTypeN snapshots, a dataset as a grid or particles"},
    [LCI_FEATURE_MPI] = {"mpi", "MPI (OpenMPI)", LC_HAVE_MPI, "libopenmpi-dev",
                         "data-parallel rendering: lc_mpi_render (lanecast_mpi.h), mpirun -np N lanecast render"},
    [LCI_FEATURE_NETCDF] = {"netcdf", "libnetcdf", LC_HAVE_NETCDF, "libnetcdf-dev",
                            "AMBER NetCDF trajectories and restarts: .nc, .ncdf, .ncrst"},
    [LCI_FEATURE_FITS] = {"fits", "cfitsio", LC_HAVE_FITS, "libcfitsio-dev",
                          "FITS float maps of projections: lc_map_write, -o map.fits"},
    [LCI_FEATURE_GDCM] = {"dicom", "GDCM", LC_HAVE_GDCM, "libgdcm-dev",
                          "DICOM series: a folder, files or one file of a CT, MR, ... series"},
};
#define NFEATURES ((int)(sizeof features / sizeof features[0]))

int lc_feature_count(void) { return NFEATURES; }

lc_status lc_feature_get(int index, lc_feature_info *out)
{
    if (index < 0 || index >= NFEATURES || !out)
        return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_feature_get: index %d is not in [0, %d) or out is NULL",
                         index, NFEATURES);
    *out = features[index];
    return LC_OK;
}

lc_status lci_missing(lc_device *dev, const char *where, const char *what, int feature)
{
    const lc_feature_info *f = &features[feature];
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: %s needs %s, which this build of lanecast lacks (install %s and rebuild)",
                     where, what, f->library, f->package);
}
