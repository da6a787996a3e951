/*
 * sphsolid/io.h - output files, checkpoints and reading them back.
 * Part of the public API of libsphsolid: include <sphsolid.h>, which
 * includes every part in order (its conventions hold for all).
 */
#ifndef SPHSOLID_PUBLIC_IO_H
#define SPHSOLID_PUBLIC_IO_H

#include "sphsolid/fields.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------- output */

/* Open an HDF5 output file (layout in docs/hdf5_layout.md).  Particle
 * snapshots are written every `snapshot_interval` steps (0: none but the
 * first) and probe samples every `probe_interval` steps (0: none; > 0
 * needs at least one probe, SPH_ERR_ARGUMENT otherwise).  The current state
 * is written as frame 0 at once. */
SPH_API sph_status sph_output_open(sph_sim *sim, const char *path, long snapshot_interval,
                                   long probe_interval);
/* Write a snapshot of the current state now. */
SPH_API sph_status sph_output_snapshot(sph_sim *sim);
/* Close the output file.  The state at closing is written first as a last
 * frame (and a last probe sample) unless the current step is already in
 * the file, so the file always ends with the final state; then the XDMF
 * companion is written beside it (sph_write_xdmf). */
SPH_API sph_status sph_output_close(sph_sim *sim);

/* Write the XDMF companion of an output file for ParaView and VTK:
 * `run.h5` -> `run.xmf` in the same folder (one grid per frame: positions,
 * velocity, density, pressure, von Mises, deviatoric stress components,
 * body), pointing into the HDF5 file.  `sim` only receives the error
 * message and may be NULL. */
SPH_API sph_status sph_write_xdmf(sph_sim *sim, const char *h5_path);

/* The version of the file format this library writes (the root attribute
 * `sphsolid_format`).  Outputs of every version from 1 (libsphsolid 0.1.0
 * and 0.2.0, written before the version was recorded) up to this one are
 * read; checkpoints of this version only. */
SPH_API int sph_output_format_version(void);

/* Number of snapshot frames in a file written by sph_output_open() (of any
 * format up to sph_output_format_version()). */
SPH_API sph_status sph_read_frame_count(sph_sim *sim, const char *path, long *frames);
/* Load frame `frame` (negative counts from the end) of a file into the
 * state of a simulation whose particles match it (same count and bodies):
 * positions, velocities, density, deviatoric stress, time and step. */
SPH_API sph_status sph_read_frame(sph_sim *sim, const char *path, long frame);

/* Write everything needed to continue the run bit for bit (state, time,
 * step, dt, motions).  Resume with sph_checkpoint_read() into a simulation
 * built the same way. */
SPH_API sph_status sph_checkpoint_write(sph_sim *sim, const char *path);
SPH_API sph_status sph_checkpoint_read(sph_sim *sim, const char *path);

#ifdef __cplusplus
}
#endif

#endif /* SPHSOLID_PUBLIC_IO_H */
