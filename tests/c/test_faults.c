/*
 * Faults while writing and reading files: a full disk during snapshots and
 * during a checkpoint, a process killed during output, damaged files, files
 * of another format or another scene, long paths.  In every case the call
 * reports the file and the cause, and the previous good data stays intact.
 *
 * A full disk is a small tmpfs when the test may mount one (root on Linux);
 * otherwise, and always in addition, writes are made to fail with
 * RLIMIT_FSIZE (SIGXFSZ ignored, so write() returns EFBIG).
 */
#define _GNU_SOURCE
#include "helpers.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "core/sim.h"

/* HDF5 1.10 keeps the core driver's buffer (and the file's name) when a
 * file's closing flush fails, as on the full disk below: the file
 * identifier is gone, so nothing outside HDF5 can free them.  LeakSanitizer
 * is told to ignore allocations made inside libhdf5; the library's own
 * allocations are still checked. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libhdf5\n"; }

/* ----------------------------------------------------------- helpers */

static sph_sim *block(int nx, int ny, double K)
{
    sph_sim *sim = new_sim(2);
    int mat, body;
    const double dx = 1e-3;
    check(sim, sph_add_material_K_mu(sim, K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {0, 0, 0}, hi[3] = {nx * dx, ny * dx, 0};
    check(sim, sph_add_block(sim, "block", mat, lo, hi, dx, &body));
    /* a small push so that the state changes from step to step */
    const double v[3] = {0, -1.0, 0};
    check(sim, sph_set_body_velocity(sim, body, v));
    return sim;
}

static long file_size(const char *path)
{
    struct stat s;
    return stat(path, &s) == 0 ? (long)s.st_size : -1;
}

static int read_all(const char *path, char **data, long *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    fseek(f, 0, SEEK_SET);
    *data = malloc((size_t)*size + 1);
    const size_t got = fread(*data, 1, (size_t)*size, f);
    fclose(f);
    return got == (size_t)*size ? 0 : -1;
}

static int same_file(const char *path, const char *data, long size)
{
    char *now = NULL;
    long n = 0;
    const int same =
        read_all(path, &now, &n) == 0 && n == size && memcmp(now, data, (size_t)n) == 0;
    free(now);
    return same;
}

/* Entries of a directory whose name starts with prefix. */
static int count_entries(const char *dir, const char *prefix)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
    if (d)
        closedir(d);
    return n;
}

/* A full disk: either a mounted tmpfs of `bytes`, or RLIMIT_FSIZE. */
typedef struct disk {
    char dir[64];
    int mounted;
    struct rlimit saved;
    int limited;
} disk;

static char mounted_dir[64];

static int disk_mount(disk *d, long bytes)
{
    snprintf(d->dir, sizeof d->dir, "/tmp/sphsolid-fault-XXXXXX");
    if (!mkdtemp(d->dir))
        return -1;
    char opts[64];
    snprintf(opts, sizeof opts, "size=%ld", bytes);
    d->mounted = geteuid() == 0 && mount("tmpfs", d->dir, "tmpfs", 0, opts) == 0;
    if (!d->mounted) {
        rmdir(d->dir);
        return -1;
    }
    memcpy(mounted_dir, d->dir, sizeof mounted_dir);
    return 0;
}

static void disk_unmount(disk *d)
{
    if (d->mounted) {
        umount2(d->dir, MNT_DETACH);
        rmdir(d->dir);
        mounted_dir[0] = '\0';
        d->mounted = 0;
    }
}

/* after a failed test: no mount and no file size limit left behind */
static int cleanup(void **state)
{
    (void)state;
    if (mounted_dir[0]) {
        umount2(mounted_dir, MNT_DETACH);
        rmdir(mounted_dir);
        mounted_dir[0] = '\0';
    }
    struct rlimit r;
    getrlimit(RLIMIT_FSIZE, &r);
    r.rlim_cur = r.rlim_max;
    setrlimit(RLIMIT_FSIZE, &r);
    return 0;
}

/* Fills the tmpfs to the byte (a filler file written until ENOSPC), then
 * frees `leave` bytes. */
static void disk_fill(const disk *d, long leave)
{
    char path[128];
    snprintf(path, sizeof path, "%s/filler", d->dir);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(fd >= 0);
    char buf[4096];
    memset(buf, 0xab, sizeof buf);
    long total = 0;
    for (;;) {
        ssize_t w = write(fd, buf, sizeof buf);
        if (w <= 0)
            break;
        total += w;
    }
    assert_int_equal(ftruncate(fd, total > leave ? total - leave : 0), 0);
    close(fd);
}

static void limit_file_size(disk *d, long bytes)
{
    signal(SIGXFSZ, SIG_IGN);
    getrlimit(RLIMIT_FSIZE, &d->saved);
    struct rlimit r = d->saved;
    r.rlim_cur = (rlim_t)bytes;
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &r), 0);
    d->limited = 1;
}

static void unlimit(disk *d)
{
    if (d->limited)
        setrlimit(RLIMIT_FSIZE, &d->saved);
    d->limited = 0;
}

/* ------------------------------------------- full disk: snapshots */

/* Snapshots every step until the disk is full: the run stops with an I/O
 * error naming the file and the cause; every frame written before reads
 * back exactly as it was. */
static void snapshots_on_a_full_disk(const char *path, disk *d, int use_limit)
{
    sph_sim *sim = block(20, 20, PAPER_K);
    const size_t n = sph_particle_count(sim);
    check(sim, sph_output_open(sim, path, 1, 0));
    const long header = file_size(path);
    const long frame_bytes = (long)n * (2 + 2 + 1 + 4 + 1 + 1) * 8;
    if (use_limit)
        limit_file_size(d, header + 3 * frame_bytes + frame_bytes / 2);
    else
        disk_fill(d, 3 * frame_bytes + frame_bytes / 2);
    /* keep the positions of every frame to compare */
    double *kept = calloc(64 * n * 2, sizeof *kept);
    long steps[64];
    memcpy(kept, sim->x, n * 2 * sizeof(double));
    steps[0] = 0;
    long written = 1;
    sph_status st = SPH_OK;
    for (int k = 0; k < 60 && st == SPH_OK; ++k) {
        st = sph_run(sim, 1);
        if (st == SPH_OK) {
            memcpy(kept + written * n * 2, sim->x, n * 2 * sizeof(double));
            steps[written++] = sph_step_count(sim);
        }
    }
    unlimit(d);
    assert_int_equal(st, SPH_ERR_IO);
    const char *msg = sph_errmsg(sim);
    assert_non_null(strstr(msg, path));
    assert_true(strstr(msg, "No space left on device") || strstr(msg, "File too large"));
    /* the file takes nothing more, and says so */
    assert_int_equal(sph_output_snapshot(sim), SPH_ERR_IO);
    assert_int_equal(sph_output_close(sim), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), path));

    long frames = -1;
    sph_sim *back = block(20, 20, PAPER_K);
    check(back, sph_read_frame_count(back, path, &frames));
    assert_true(frames >= 2);
    assert_true(frames <= written);
    for (long k = 0; k < frames; ++k) {
        check(back, sph_read_frame(back, path, k));
        assert_int_equal(sph_step_count(back), steps[k]);
        assert_memory_equal(back->x, kept + k * n * 2, n * 2 * sizeof(double));
        for (size_t a = 0; a < n; ++a)
            assert_true(back->rho[a] > 0.0);
    }
    assert_int_equal(sph_read_frame(back, path, frames), SPH_ERR_ARGUMENT);
    free(kept);
    sph_destroy(back);
    sph_destroy(sim);
}

static void full_disk_during_snapshots_keeps_earlier_frames(void **state)
{
    (void)state;
    disk d = {0};
    if (disk_mount(&d, 4 << 20) == 0) {
        char path[128];
        snprintf(path, sizeof path, "%s/run.h5", d.dir);
        snapshots_on_a_full_disk(path, &d, 0);
        disk_unmount(&d);
    } else {
        print_message("tmpfs not available: full disk simulated with RLIMIT_FSIZE only\n");
    }
    snapshots_on_a_full_disk("test_faults_limit.h5", &d, 1);
    remove("test_faults_limit.h5");
}

/* ------------------------------------------- full disk: checkpoint */

static void checkpoint_on_a_full_disk(const char *dir, disk *d, int use_limit)
{
    char path[256];
    snprintf(path, sizeof path, "%s/state.h5", dir);
    /* 64 x 64 particles: a checkpoint of about 330 kB, so the disk fills
     * while its image is written, not when the temporary file is made */
    sph_sim *sim = block(64, 64, PAPER_K);
    check(sim, sph_run(sim, 5));
    check(sim, sph_checkpoint_write(sim, path));
    char *good = NULL;
    long good_size = 0;
    assert_int_equal(read_all(path, &good, &good_size), 0);
    const size_t n = sph_particle_count(sim);
    double *x5 = malloc(n * 2 * sizeof *x5);
    memcpy(x5, sim->x, n * 2 * sizeof *x5);

    check(sim, sph_run(sim, 5));
    if (use_limit)
        limit_file_size(d, good_size / 2);
    else
        disk_fill(d, good_size / 2);
    const sph_status st = sph_checkpoint_write(sim, path);
    unlimit(d);
    assert_int_equal(st, SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), path));
    assert_true(strstr(sph_errmsg(sim), "No space left on device") ||
                strstr(sph_errmsg(sim), "File too large"));
    assert_non_null(strstr(sph_errmsg(sim), "previous file is unchanged"));
    assert_non_null(strstr(sph_errmsg(sim), "(write '"));
    /* the previous checkpoint is byte for byte the same, no temporary
     * file is left, and it still loads */
    assert_true(same_file(path, good, good_size));
    assert_int_equal(count_entries(dir, "state.h5.tmp"), 0);
    sph_sim *back = block(64, 64, PAPER_K);
    check(back, sph_checkpoint_read(back, path));
    assert_int_equal(sph_step_count(back), 5);
    assert_memory_equal(back->x, x5, n * 2 * sizeof(double));
    /* with room again the same call succeeds */
    if (!use_limit) {
        char filler[256];
        snprintf(filler, sizeof filler, "%s/filler", dir);
        remove(filler);
    }
    check(sim, sph_checkpoint_write(sim, path));
    check(back, sph_checkpoint_read(back, path));
    assert_int_equal(sph_step_count(back), 10);
    free(x5);
    free(good);
    sph_destroy(back);
    sph_destroy(sim);
    remove(path);
}

static void full_disk_during_checkpoint_keeps_previous_checkpoint(void **state)
{
    (void)state;
    disk d = {0};
    if (disk_mount(&d, 4 << 20) == 0) {
        checkpoint_on_a_full_disk(d.dir, &d, 0);
        disk_unmount(&d);
    } else {
        print_message("tmpfs not available: full disk simulated with RLIMIT_FSIZE only\n");
    }
    char dir[] = "test_faults_ckpt-XXXXXX";
    assert_non_null(mkdtemp(dir));
    checkpoint_on_a_full_disk(dir, &d, 1);
    rmdir(dir);
}

/* ------------------------------------------------ kill -9 during output */

static const char *self_path;

/* The child of the kill test: snapshots and probe samples every step, one
 * byte on the pipe after each step, until killed. */
static int writer(const char *path, int fd)
{
    sph_sim *sim = block(30, 30, PAPER_K);
    const double point[3] = {0.015, 0.015, 0};
    if (sph_add_probe(sim, "centre", point, NULL) || sph_output_open(sim, path, 1, 1))
        return 2;
    for (;;) {
        if (sph_run(sim, 1))
            return 3;
        const char c = 1;
        if (write(fd, &c, 1) != 1)
            return 4;
    }
}

static void killed_during_output_leaves_readable_frames(void **state)
{
    (void)state;
    const char *path = "test_faults_killed.h5";
    for (int trial = 0; trial < 4; ++trial) {
        int fds[2];
        assert_int_equal(pipe(fds), 0);
        const pid_t pid = fork();
        assert_true(pid >= 0);
        if (pid == 0) {
            /* a fresh process (OpenMP's threads do not survive fork) */
            close(fds[0]);
            char fd_arg[16];
            snprintf(fd_arg, sizeof fd_arg, "%d", fds[1]);
            execl(self_path, self_path, "--writer", path, fd_arg, (char *)NULL);
            _exit(5);
        }
        close(fds[1]);
        char c;
        for (int k = 0; k < 3 + trial; ++k)
            assert_int_equal(read(fds[0], &c, 1), 1);
        /* kill at a different point of the next write each trial */
        const struct timespec pause = {0, 200000L * trial};
        nanosleep(&pause, NULL);
        kill(pid, SIGKILL);
        int status = 0;
        waitpid(pid, &status, 0);
        close(fds[0]);
        assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);

        sph_sim *back = block(30, 30, PAPER_K);
        long frames = 0;
        check(back, sph_read_frame_count(back, path, &frames));
        assert_true(frames >= 3 + trial);
        for (long k = 0; k < frames; ++k) {
            check(back, sph_read_frame(back, path, k));
            assert_int_equal(sph_step_count(back), k);
        }
        sph_destroy(back);
        remove(path);
    }
}

#if H5_VERSION_GE(1, 10, 5)
/* Chunks of several rows are rewritten in place as a series grows; those
 * holding rows readers already trust must lie within one page (see
 * io_hdf5.c), so that a process killed during the rewrite cannot leave a
 * chunk half old, half new, whose checksum then fails. */
#if H5_VERSION_GE(1, 12, 0)
typedef H5O_info2_t object_info;
#define VISIT(file, op, data) \
    H5Ovisit3(file, H5_INDEX_NAME, H5_ITER_NATIVE, op, data, H5O_INFO_BASIC)
#else
typedef H5O_info_t object_info;
#define VISIT(file, op, data) \
    H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_NATIVE, op, data, H5O_INFO_BASIC)
#endif

static int chunk_crosses_page(hid_t obj, const char *name, const object_info *info, void *data)
{
    int *crossing = data;
    if (info->type != H5O_TYPE_DATASET)
        return 0;
    hid_t d = H5Dopen2(obj, name, H5P_DEFAULT);
    hid_t dcpl = H5Dget_create_plist(d);
    hid_t space = H5Dget_space(d);
    hsize_t chunk_dims[4] = {0}, dims[4], max_dims[4] = {0};
    H5Sget_simple_extent_dims(space, dims, max_dims);
    /* a series (extended as it grows) with several rows per chunk */
    if (max_dims[0] == H5S_UNLIMITED && H5Pget_layout(dcpl) == H5D_CHUNKED &&
        H5Pget_chunk(dcpl, 4, chunk_dims) > 0 && chunk_dims[0] > 1) {
        hsize_t chunks = 0;
        H5Dget_num_chunks(d, space, &chunks);
        for (hsize_t k = 0; k < chunks; ++k) {
            hsize_t offset[4];
            unsigned mask;
            haddr_t addr;
            hsize_t size;
            assert_true(H5Dget_chunk_info(d, space, k, offset, &mask, &addr, &size) >= 0);
            if (addr / 4096 != (addr + size - 1) / 4096) {
                fprintf(stderr, "chunk %llu of %s (%llu bytes at %llu) crosses a page\n",
                        (unsigned long long)k, name, (unsigned long long)size,
                        (unsigned long long)addr);
                ++*crossing;
            }
        }
    }
    H5Sclose(space);
    H5Pclose(dcpl);
    H5Dclose(d);
    return 0;
}

static void rewritten_chunks_lie_within_one_page(void **state)
{
    (void)state;
    const char *path = "test_faults_pages.h5";
    /* probe sets of 1, 3 and 40 points: value rows of 8, 24... bytes */
    const int probe_counts[3] = {1, 3, 40};
    for (int p = 0; p < 3; ++p) {
        sph_sim *sim = block(30, 30, PAPER_K);
        for (int k = 0; k < probe_counts[p]; ++k) {
            char name[16];
            snprintf(name, sizeof name, "p%d", k);
            const double point[3] = {0.002 + 0.0005 * k, 0.015, 0};
            check(sim, sph_add_probe(sim, name, point, NULL));
        }
        check(sim, sph_output_open(sim, path, 7, 1));
        check(sim, sph_run(sim, 300));
        check(sim, sph_output_close(sim));
        sph_destroy(sim);

        hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
        assert_true(file >= 0);
        int crossing = 0;
        assert_true(VISIT(file, chunk_crosses_page, &crossing) >= 0);
        H5Fclose(file);
        assert_int_equal(crossing, 0);
        remove(path);
    }
}
#endif

/* --------------------------------------------------- damaged files */

/* Flips one byte inside the stored copy of `value` (8 bytes) in the file. */
static int damage_at_value(const char *path, const double *value)
{
    char *data = NULL;
    long size = 0;
    if (read_all(path, &data, &size))
        return -1;
    long at = -1;
    for (long i = 0; i + 8 <= size; ++i)
        if (memcmp(data + i, value, 8) == 0) {
            at = i;
            break;
        }
    free(data);
    if (at < 0)
        return -1;
    FILE *f = fopen(path, "r+b");
    fseek(f, at + 6, SEEK_SET);
    unsigned char b = 0;
    assert_int_equal(fread(&b, 1, 1, f), 1);
    b ^= 0x5f;
    fseek(f, at + 6, SEEK_SET);
    fwrite(&b, 1, 1, f);
    fclose(f);
    return 0;
}

static void damaged_checkpoint_is_refused_and_state_kept(void **state)
{
    (void)state;
    const char *path = "test_faults_damaged.h5";
    sph_sim *sim = block(20, 20, PAPER_K);
    check(sim, sph_run(sim, 3));
    check(sim, sph_checkpoint_write(sim, path));
    const size_t n = sph_particle_count(sim);
    /* a distinctive velocity value to find in the file */
    assert_int_equal(damage_at_value(path, &sim->v[2 * 37 + 1]), 0);

    sph_sim *back = block(20, 20, PAPER_K);
    check(back, sph_run(back, 1));
    double *x = malloc(n * 2 * sizeof *x), *v = malloc(n * 2 * sizeof *v);
    memcpy(x, back->x, n * 2 * sizeof *x);
    memcpy(v, back->v, n * 2 * sizeof *v);
    assert_int_equal(sph_checkpoint_read(back, path), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(back), path));
    assert_non_null(strstr(sph_errmsg(back), "velocity"));
    assert_non_null(strstr(sph_errmsg(back), "checksum"));
    /* nothing changed */
    assert_memory_equal(back->x, x, n * 2 * sizeof *x);
    assert_memory_equal(back->v, v, n * 2 * sizeof *v);
    assert_int_equal(sph_step_count(back), 1);
    free(x);
    free(v);
    sph_destroy(back);
    sph_destroy(sim);
    remove(path);
}

static void damaged_frame_is_refused_and_state_kept(void **state)
{
    (void)state;
    const char *path = "test_faults_damaged_frame.h5";
    sph_sim *sim = block(20, 20, PAPER_K);
    check(sim, sph_output_open(sim, path, 2, 0));
    check(sim, sph_run(sim, 4));
    check(sim, sph_output_close(sim));
    assert_int_equal(damage_at_value(path, &sim->x[2 * 101 + 1]), 0); /* y changes every step */
    sph_sim *back = block(20, 20, PAPER_K);
    const size_t n = sph_particle_count(sim);
    double *x = malloc(n * 2 * sizeof *x);
    memcpy(x, back->x, n * 2 * sizeof *x);
    assert_int_equal(sph_read_frame(back, path, -1), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(back), "position"));
    assert_non_null(strstr(sph_errmsg(back), "checksum"));
    assert_memory_equal(back->x, x, n * 2 * sizeof *x);
    assert_int_equal(sph_step_count(back), 0);
    /* the earlier frames are intact */
    check(back, sph_read_frame(back, path, 1));
    assert_int_equal(sph_step_count(back), 2);
    free(x);
    sph_destroy(back);
    sph_destroy(sim);
    remove(path);
}

static void truncated_and_foreign_files_are_refused(void **state)
{
    (void)state;
    const char *path = "test_faults_truncated.h5";
    sph_sim *sim = block(20, 20, PAPER_K);
    check(sim, sph_checkpoint_write(sim, path));
    const long size = file_size(path);
    assert_int_equal(truncate(path, size / 2), 0);
    assert_int_equal(sph_checkpoint_read(sim, path), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), path));
    /* a text file */
    FILE *f = fopen(path, "w");
    fputs("not an HDF5 file\n", f);
    fclose(f);
    assert_int_equal(sph_checkpoint_read(sim, path), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), "as an HDF5 file"));
    assert_int_equal(sph_read_frame(sim, path, 0), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), path));
    /* an output file is not a checkpoint, and the reverse */
    check(sim, sph_output_open(sim, path, 0, 0));
    check(sim, sph_output_close(sim));
    assert_int_equal(sph_checkpoint_read(sim, path), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), "not a checkpoint"));
    check(sim, sph_checkpoint_write(sim, path));
    assert_int_equal(sph_read_frame(sim, path, 0), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), "not an output file"));
    sph_destroy(sim);
    remove(path);
}

/* A file as the library wrote it before the format was versioned (the old
 * checkpoint layout: a /checkpoint group, no sphsolid_format), and one that
 * claims a newer version. */
static void old_and_newer_formats_are_refused(void **state)
{
    (void)state;
    const char *path = "test_faults_old.h5";
    hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    hid_t g = H5Gcreate2(f, "checkpoint", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    hid_t sp = H5Screate(H5S_SCALAR);
    const long one = 400;
    hid_t a = H5Acreate2(g, "particles", H5T_NATIVE_LONG, sp, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_LONG, &one);
    H5Aclose(a);
    H5Gclose(g);
    H5Fclose(f);
    sph_sim *sim = block(20, 20, PAPER_K);
    const double x0 = sim->x[10];
    assert_int_equal(sph_checkpoint_read(sim, path), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), "format 1"));
    assert_non_null(strstr(sph_errmsg(sim), path));
    assert_true(sim->x[10] == x0);

    f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    const long three = 3;
    a = H5Acreate2(f, "sphsolid_format", H5T_NATIVE_LONG, sp, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_LONG, &three);
    H5Aclose(a);
    H5Fclose(f);
    H5Sclose(sp);
    assert_int_equal(sph_checkpoint_read(sim, path), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), "format 3"));
    sph_destroy(sim);
    remove(path);
}

/* An output of libsphsolid 0.1.0 (file format 1, no version attribute, no
 * complete_frames count, no checksums; tests/data/make_format1_output.c)
 * reads back into the same scene built with this API: a free block pushed
 * at a uniform 1 m/s has no internal rates, so frame k holds the lattice
 * moved by -1 m/s x k dt, the velocity, rho0 and zero stress. */
static void format_1_output_is_read(void **state)
{
    (void)state;
    const char *path = SPHSOLID_TEST_DATA "/format1_output.h5";
    sph_sim *sim = new_sim(2);
    int mat, body;
    check(sim, sph_add_material_K_mu(sim, PAPER_K, PAPER_MU, PAPER_RHO0, &mat));
    const double lo[3] = {0, 0, 0}, hi[3] = {6e-3, 4e-3, 0}, v[3] = {0, -1.0, 0};
    check(sim, sph_add_block(sim, "block", mat, lo, hi, 1e-3, &body));
    check(sim, sph_set_body_velocity(sim, body, v));
    const size_t n = sph_particle_count(sim);
    assert_int_equal(n, 24);
    double x0[48];
    memcpy(x0, sim->x, sizeof x0);
    long frames = 0;
    check(sim, sph_read_frame_count(sim, path, &frames));
    assert_int_equal(frames, 4);
    for (long k = 0; k < frames; ++k) {
        check(sim, sph_read_frame(sim, path, k));
        assert_int_equal(sph_step_count(sim), k);
        assert_close(sph_time(sim), 1e-7 * (double)k, 1e-22, "frame time");
        for (size_t a = 0; a < n; ++a) {
            assert_close(sim->x[2 * a], x0[2 * a], 1e-15, "x");
            assert_close(sim->x[2 * a + 1], x0[2 * a + 1] - 1e-7 * (double)k, 1e-15, "y");
            assert_close(sim->v[2 * a + 1], -1.0, 1e-12, "vy");
            assert_close(sim->rho[a], PAPER_RHO0, 1e-9, "density");
            for (int c = 0; c < 4; ++c)
                assert_close(sim->S[4 * a + (size_t)c], 0.0, 1e-6, "deviatoric stress");
        }
    }
    /* the run goes on from the frame read */
    check(sim, sph_run(sim, 1));
    assert_int_equal(sph_step_count(sim), 4);
    /* another scene is refused (format 1 records no body extents: a body
     * of the same name and count but another shape is not told apart) */
    sph_sim *other = free_block_2d(5, 4, 1e-3);
    assert_int_equal(sph_read_frame(other, path, 0), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(other), "does not match this simulation"));
    /* it is an output, not a checkpoint */
    assert_int_equal(sph_checkpoint_read(sim, path), SPH_ERR_IO);
    assert_non_null(strstr(sph_errmsg(sim), "output file (format 1), not a checkpoint"));
    sph_destroy(other);
    sph_destroy(sim);
}

/* The format version exported is the one written into each file. */
static void written_format_is_the_exported_version(void **state)
{
    (void)state;
    char dir[] = "/tmp/sphsolid-format-XXXXXX", path[64], xmf[64];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/out.h5", dir);
    snprintf(xmf, sizeof xmf, "%s/out.xmf", dir);
    sph_sim *sim = block(4, 4, PAPER_K);
    check(sim, sph_output_open(sim, path, 1, 0));
    check(sim, sph_output_close(sim));
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    long version = 0;
    hid_t a = H5Aopen(f, "sphsolid_format", H5P_DEFAULT);
    assert_true(H5Aread(a, H5T_NATIVE_LONG, &version) >= 0);
    H5Aclose(a);
    H5Fclose(f);
    assert_int_equal(version, sph_output_format_version());
    assert_true(sph_output_format_version() >= 2);
    sph_destroy(sim);
    remove(path);
    remove(xmf);
    rmdir(dir);
}

/* ---------------------------------------------------- another scene */

static void checkpoint_of_another_scene_names_the_difference(void **state)
{
    (void)state;
    const char *path = "test_faults_scene.h5";
    sph_sim *sim = block(20, 30, PAPER_K);
    check(sim, sph_run(sim, 2));
    check(sim, sph_checkpoint_write(sim, path));

    /* same particle count, another shape */
    sph_sim *other = block(30, 20, PAPER_K);
    const double x0 = other->x[7];
    assert_int_equal(sph_checkpoint_read(other, path), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(other), "body 'block' spans"));
    assert_true(other->x[7] == x0);
    assert_int_equal(sph_step_count(other), 0);
    sph_destroy(other);

    /* another material */
    other = block(20, 30, 2.0 * PAPER_K);
    assert_int_equal(sph_checkpoint_read(other, path), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(other), "bulk modulus K"));
    sph_destroy(other);

    /* another motion */
    other = block(20, 30, PAPER_K);
    check(other, sph_set_motion(other, 0, SPH_MOTION_FIXED, NULL));
    assert_int_equal(sph_checkpoint_read(other, path), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(other), "motion 'free' in the file, motion 'fixed' here"));
    sph_destroy(other);

    /* frames too */
    const char *out = "test_faults_scene_frames.h5";
    check(sim, sph_output_open(sim, out, 0, 0));
    check(sim, sph_output_close(sim));
    other = block(30, 20, PAPER_K);
    assert_int_equal(sph_read_frame(other, out, 0), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(other), "spans"));
    sph_destroy(other);
    sph_destroy(sim);
    remove(path);
    remove(out);
}

/* The effects a checkpoint was written with, one attribute per parameter
 * under /parameters/effects: a simulation with other effects is refused
 * naming the effect and parameter; a file written before that group
 * (only the effects text) is compared by its text. */
static void checkpoint_with_other_effects_names_the_difference(void **state)
{
    (void)state;
    const char *path = "test_faults_effects.h5";
    sph_sim *sim = block(20, 30, PAPER_K);
    check(sim, sph_effect(sim, "artificial_viscosity", "alpha=1 beta=0"));
    check(sim, sph_effect(sim, "gravity", "gy=-9.81"));
    check(sim, sph_run(sim, 2));
    check(sim, sph_checkpoint_write(sim, path));

    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    double alpha = 0.0, gy = 0.0;
    hid_t a = H5Aopen_by_name(f, "parameters/effects/artificial_viscosity", "alpha", H5P_DEFAULT,
                              H5P_DEFAULT);
    assert_true(a >= 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &alpha) >= 0);
    H5Aclose(a);
    a = H5Aopen_by_name(f, "parameters/effects/gravity", "gy", H5P_DEFAULT, H5P_DEFAULT);
    assert_true(a >= 0 && H5Aread(a, H5T_NATIVE_DOUBLE, &gy) >= 0);
    H5Aclose(a);
    assert_true(alpha == 1.0 && gy == -9.81);
    assert_true(H5Lexists(f, "parameters/effects/xsph", H5P_DEFAULT) == 0);
    H5Fclose(f);

    static const char *const others[][3] = {
        /* effect, its parameters (NULL: off), the words of the message */
        {"artificial_viscosity", "alpha=0.5 beta=0", "alpha=1 in the file, alpha=0.5 here"},
        {"artificial_viscosity", NULL, "artificial_viscosity is on in the file, off here"},
        {"xsph", "epsilon=0.5", "xsph is off in the file, on here"},
    };
    for (int k = 0; k < 3; ++k) {
        sph_sim *other = block(20, 30, PAPER_K);
        check(other, sph_effect(other, "artificial_viscosity", "alpha=1 beta=0"));
        check(other, sph_effect(other, "gravity", "gy=-9.81"));
        if (others[k][1])
            check(other, sph_effect(other, others[k][0], others[k][1]));
        else
            check(other, sph_effect_off(other, others[k][0]));
        const double x0 = other->x[7];
        assert_int_equal(sph_checkpoint_read(other, path), SPH_ERR_ARGUMENT);
        assert_non_null(strstr(sph_errmsg(other), others[k][2]));
        assert_true(other->x[7] == x0);
        sph_destroy(other);
    }
    sph_sim *same = block(20, 30, PAPER_K);
    check(same, sph_effect(same, "artificial_viscosity", "alpha=1 beta=0"));
    check(same, sph_effect(same, "gravity", "gy=-9.81"));
    check(same, sph_checkpoint_read(same, path));

    /* a checkpoint from before the per-parameter record */
    f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    assert_true(H5Ldelete(f, "parameters/effects", H5P_DEFAULT) >= 0);
    H5Fclose(f);
    check(same, sph_checkpoint_read(same, path));
    check(same, sph_effect(same, "artificial_viscosity", "alpha=0.5 beta=0"));
    assert_int_equal(sph_checkpoint_read(same, path), SPH_ERR_ARGUMENT);
    assert_non_null(strstr(sph_errmsg(same), "effects 'artificial_viscosity alpha=1 beta=0;"));
    sph_destroy(same);
    sph_destroy(sim);
    remove(path);
}

static void adding_a_body_while_output_is_open_is_refused(void **state)
{
    (void)state;
    const char *path = "test_faults_addbody.h5";
    sph_sim *sim = block(10, 10, PAPER_K);
    check(sim, sph_output_open(sim, path, 1, 0));
    const double lo[3] = {0.1, 0.1, 0}, hi[3] = {0.11, 0.11, 0};
    assert_int_equal(sph_add_block(sim, "late", 0, lo, hi, 1e-3, NULL), SPH_ERR_STATE);
    assert_non_null(strstr(sph_errmsg(sim), "late"));
    assert_non_null(strstr(sph_errmsg(sim), "output file"));
    check(sim, sph_output_close(sim));
    sph_destroy(sim);
    remove(path);
}

/* ------------------------------------------ output file moved away */

/* The output file removed or replaced (another file renamed over its path)
 * during a run: the next write stops the run with an error naming the path,
 * closing reports it, and no XDMF is written (it would describe a file the
 * run did not write); the replacing file is left as it was.  Untouched, the
 * same run writes its XDMF.  Modes: 0 untouched, 1 removed, 2 replaced,
 * 3 replaced after the last write (found at close). */
static void output_file_removed_or_replaced_is_an_error(void **state)
{
    (void)state;
    static const char other[] = "another program's file\n";
    for (int mode = 0; mode < 4; ++mode) {
        char dir[] = "/tmp/sphsolid-moved-XXXXXX";
        assert_non_null(mkdtemp(dir));
        char path[64], xmf[64], elsewhere[64];
        snprintf(path, sizeof path, "%s/out.h5", dir);
        snprintf(xmf, sizeof xmf, "%s/out.xmf", dir);
        snprintf(elsewhere, sizeof elsewhere, "%s/other", dir);
        sph_sim *sim = block(10, 10, PAPER_K);
        check(sim, sph_output_open(sim, path, 1, 0));
        check(sim, sph_run(sim, 3));
        if (mode >= 2) {
            FILE *f = fopen(elsewhere, "wb");
            assert_non_null(f);
            fputs(other, f);
            fclose(f);
            assert_int_equal(rename(elsewhere, path), 0);
        } else if (mode == 1) {
            assert_int_equal(unlink(path), 0);
        }
        const char *what = mode == 1 ? "was removed during the run" : "was replaced during the run";
        if (mode == 1 || mode == 2) {
            assert_int_equal(sph_run(sim, 3), SPH_ERR_IO);
            assert_non_null(strstr(sph_errmsg(sim), path));
            assert_non_null(strstr(sph_errmsg(sim), what));
            assert_int_equal(sph_step_count(sim), 4); /* stopped at the first write */
        }
        const sph_status closed = sph_output_close(sim);
        if (mode == 0) {
            assert_int_equal(closed, SPH_OK);
            assert_int_equal(access(xmf, F_OK), 0);
        } else {
            assert_int_equal(closed, SPH_ERR_IO);
            assert_non_null(strstr(sph_errmsg(sim), what));
            assert_int_equal(access(xmf, F_OK), -1); /* no XDMF of a file not written */
        }
        if (mode >= 2)
            assert_true(same_file(path, other, (long)strlen(other)));
        sph_destroy(sim);
        remove(path);
        remove(xmf);
        assert_int_equal(rmdir(dir), 0);
    }
}

/* ----------------------------------------------------- long paths */

static void long_checkpoint_path_touches_no_other_file(void **state)
{
    (void)state;
    /* a path of about 1,400 characters in nested directories */
    char path[2048] = "test_faults_long";
    mkdir(path, 0755);
    for (int k = 0; k < 6; ++k) {
        strcat(path, "/");
        const size_t at = strlen(path);
        memset(path + at, 'a' + k, 200);
        path[at + 200] = '\0';
        assert_int_equal(mkdir(path, 0755), 0);
    }
    strcat(path, "/checkpoint.h5");
    assert_true(strlen(path) > 1200);
    /* an unrelated file named like a truncated temporary name */
    char prefix[2048];
    snprintf(prefix, sizeof prefix, "%.*s", 1099, path);
    char unrelated[2100];
    snprintf(unrelated, sizeof unrelated, "%s", prefix);
    int fd = open(unrelated, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int have_unrelated = fd >= 0;
    if (fd >= 0) {
        assert_int_equal(write(fd, "keep", 4), 4);
        close(fd);
    }
    sph_sim *sim = block(10, 10, PAPER_K);
    check(sim, sph_run(sim, 2));
    check(sim, sph_checkpoint_write(sim, path));
    if (have_unrelated)
        assert_true(same_file(unrelated, "keep", 4));
    sph_sim *back = block(10, 10, PAPER_K);
    check(back, sph_checkpoint_read(back, path));
    assert_int_equal(sph_step_count(back), 2);
    /* output files too */
    strcat(path, ".out");
    check(sim, sph_output_open(sim, path, 1, 0));
    check(sim, sph_run(sim, 2));
    check(sim, sph_output_close(sim));
    long frames = 0;
    check(back, sph_read_frame_count(back, path, &frames));
    assert_int_equal(frames, 3);
    sph_destroy(back);
    sph_destroy(sim);
    assert_int_equal(system("rm -rf test_faults_long"), 0);
}

/* ---------------------------------------- the host's HDF5 error handler */

static int host_calls;
static herr_t host_handler(hid_t stack, void *data)
{
    (void)stack;
    (void)data;
    host_calls++;
    return 0;
}

static void host_hdf5_error_handler_is_kept(void **state)
{
    (void)state;
    H5Eset_auto2(H5E_DEFAULT, host_handler, NULL);
    sph_sim *sim = block(10, 10, PAPER_K);
    assert_int_equal(sph_checkpoint_read(sim, "no/such/checkpoint.h5"), SPH_ERR_IO);
    assert_int_equal(sph_read_frame(sim, "test_faults.c", 0), SPH_ERR_IO);
    check(sim, sph_checkpoint_write(sim, "test_faults_host.h5"));
    check(sim, sph_checkpoint_read(sim, "test_faults_host.h5"));
    /* the library's own failures did not reach the host's handler ... */
    assert_int_equal(host_calls, 0);
    H5E_auto2_t func = NULL;
    void *data = NULL;
    H5Eget_auto2(H5E_DEFAULT, &func, &data);
    assert_true(func == host_handler);
    /* ... and the host's own failures still do */
    hid_t f = H5Fopen("no/such/file.h5", H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(f < 0);
    assert_int_equal(host_calls, 1);
    H5Eset_auto2(H5E_DEFAULT, (H5E_auto2_t)H5Eprint2, stderr);
    sph_destroy(sim);
    remove("test_faults_host.h5");
}

int main(int argc, char **argv)
{
    self_path = argv[0];
    if (argc == 4 && strcmp(argv[1], "--writer") == 0)
        return writer(argv[2], atoi(argv[3]));
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_teardown(full_disk_during_snapshots_keeps_earlier_frames, cleanup),
        cmocka_unit_test_teardown(full_disk_during_checkpoint_keeps_previous_checkpoint, cleanup),
        cmocka_unit_test_teardown(killed_during_output_leaves_readable_frames, cleanup),
#if H5_VERSION_GE(1, 10, 5)
        cmocka_unit_test_teardown(rewritten_chunks_lie_within_one_page, cleanup),
#endif
        cmocka_unit_test_teardown(damaged_checkpoint_is_refused_and_state_kept, cleanup),
        cmocka_unit_test_teardown(damaged_frame_is_refused_and_state_kept, cleanup),
        cmocka_unit_test_teardown(truncated_and_foreign_files_are_refused, cleanup),
        cmocka_unit_test_teardown(old_and_newer_formats_are_refused, cleanup),
        cmocka_unit_test_teardown(format_1_output_is_read, cleanup),
        cmocka_unit_test_teardown(written_format_is_the_exported_version, cleanup),
        cmocka_unit_test_teardown(checkpoint_of_another_scene_names_the_difference, cleanup),
        cmocka_unit_test_teardown(checkpoint_with_other_effects_names_the_difference, cleanup),
        cmocka_unit_test_teardown(adding_a_body_while_output_is_open_is_refused, cleanup),
        cmocka_unit_test_teardown(output_file_removed_or_replaced_is_an_error, cleanup),
        cmocka_unit_test_teardown(long_checkpoint_path_touches_no_other_file, cleanup),
        cmocka_unit_test_teardown(host_hdf5_error_handler_is_kept, cleanup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
