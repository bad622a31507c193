/* Voxel-to-world matrices onto lanecast's axis-aligned grids (NIfTI sform
 * and qform, DICOM image position and orientation): the nearest axis
 * permutation with flips, and the voxels reordered onto it. */
#ifndef LC_HOST_ORIENT_H
#define LC_HOST_ORIENT_H

#include <stdint.h>

/* The nearest axis-aligned frame of matrix m (world = m * (i, j, k, 1)):
 * perm[w] = the voxel axis put on world axis w, flip[w] = 1 when it runs
 * against it, spacing[w] = that voxel axis' length, origin[w] = the world
 * position of the reordered grid's first node. Exact (every voxel where m
 * puts it) when m is a scaled permutation with flips (every other component
 * below 1e-6 of its column); otherwise the voxel sizes and the volume's
 * centre are kept. Returns the largest angle in degrees between a voxel
 * axis and its world axis: 0 when exact. */
double lci_axis_frame(const double m[3][4], const int64_t n[3], int perm[3], int flip[3], double spacing[3],
                      double origin[3]);
/* Copies the n[0] x n[1] x n[2] voxels of es bytes each of src (x fastest)
 * into dst in the frame lci_axis_frame chose: dst's axis w is src's axis
 * perm[w], reversed where flip[w]. */
void lci_axis_reorder(const void *src, void *dst, int es, const int64_t n[3], const int perm[3], const int flip[3]);

#endif
