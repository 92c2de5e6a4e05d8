/* Files a program reads and writes: outputs checked before any work (tools/app/outputs.c),
 * whole files, folders, atomic writes of images, JSON and text, hashes (tools/app/common.c). */
#ifndef LUMIS_APP_FILES_H
#define LUMIS_APP_FILES_H

#include "lumis/io.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Writes with the atomic writer; prints errors itself. */
lumis_status tool_write_image(const char *path, const lumis_image *image,
                              const lumis_write_options *options);

typedef enum tool_output_kind {
    TOOL_OUT_FILE,   /* any name (JSON, CSV, text) */
    TOOL_OUT_IMAGE,  /* .exr .hdr .pfm .png */
    TOOL_OUT_LINEAR, /* .exr .hdr .pfm: linear values */
    TOOL_OUT_PNG,    /* .png */
    TOOL_OUT_GLTF,   /* .gltf (text) or .glb (binary) */
    TOOL_OUT_DIR,    /* a directory, made if missing (its parent must exist) */
    TOOL_OUT_SIDECAR /* a render's JSON sidecar: replaces only an earlier sidecar */
} tool_output_kind;

enum { TOOL_FILES_MAX = 32 };

/* The files a command reads and writes. */
typedef struct tool_files {
    int n_in, n_out;
    struct {
        const char *what, *path;
        tool_output_kind kind;
        const char *hint; /* TOOL_OUT_SIDECAR: the options that choose another path */
    } in[TOOL_FILES_MAX], out[TOOL_FILES_MAX];
    int n_lists; /* inputs by the list: a luminaire's images (borrowed until the check) */
    struct {
        const char *what;
        const char *const *paths;
        int count;
    } lists[TOOL_FILES_MAX];
} tool_files;

/* Records an input or an output; what names it in messages ("scene file", "--png").  NULL
 * or empty paths are ignored. */
void tool_files_input(tool_files *f, const char *what, const char *path);
void tool_files_output(tool_files *f, const char *what, const char *path, tool_output_kind kind);
/* Records a sidecar output: it may replace an earlier sidecar (tool_is_sidecar) or an empty
 * file, nothing else; hint names the options that choose another path ("--sidecar PATH or
 * --no-sidecar"). */
void tool_files_sidecar(tool_files *f, const char *path, const char *hint);
/* Nonzero when path holds a lumis sidecar: a JSON object with "lumis_version", "command"
 * and "outputs", as tool_write_sidecar writes it. */
int tool_is_sidecar(const char *path);
/* Records count inputs at once (the paths are borrowed until tool_files_check). */
void tool_files_input_list(tool_files *f, const char *what, const char *const *paths, int count);

/* The whole of a file (free it); NULL if it cannot be opened (*oom = 0) or memory is short
 * (*oom = 1). */
unsigned char *tool_read_file(const char *path, size_t *n, int *oom);

/* Usage error (exit 2, naming both paths) unless every output has an extension of its kind,
 * a directory that exists and can be written, and is neither an input nor another output;
 * a sidecar may replace only a sidecar.
 * Same file: by device and inode when both exist, else by resolved directory and name. */
int tool_files_check(const char *cmd, const tool_files *f);
int tool_same_file(const char *a, const char *b);

/* FNV-1a (64-bit) of n bytes, continued from h (start: 0xcbf29ce484222325): the cache keys
 * of lumis bench and of acquired luminaires. */
uint64_t tool_fnv(uint64_t h, const void *data, size_t n);
/* mkdir -p; prints the error.  Exit code. */
int tool_make_dir(const char *path);
/* Writes a text built in a FILE* (tmpfile(); NULL: an error) atomically to path, and
 * closes f.  Exit code. */
int tool_commit_tmp(FILE *f, const char *path);
/* s written to f with HTML's and SVG's special characters (< > & ") as entities. */
void tool_markup_escape(FILE *f, const char *s);

struct cJSON;
/* Writes a JSON object (struct cJSON), indented and ending in a newline, with the atomic
 * writer; prints errors itself.  Exit code. */
int tool_write_json(const char *path, const struct cJSON *json);

#endif
