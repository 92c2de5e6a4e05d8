/* Table-driven option parsing for the lumis commands (tools/lumis/optparse.c).
 *
 * Each command describes its options once, as an array of tool_opt records: the name (and
 * an alias such as -o), the value's metavar, a help text, what kind of value it takes (with
 * the range a number must lie in, or the parser or handler of anything else) and where in
 * the command's context structure the value goes.  One parser reads argv against the table,
 * and the same table gives the command's --help, `lumis help --markdown` and
 * docs/options.md: an option's name, metavar and help exist in exactly one place. */
#ifndef LUMIS_TOOL_OPTPARSE_H
#define LUMIS_TOOL_OPTPARSE_H

#include <stddef.h>
#include <stdio.h>

typedef enum tool_opt_kind {
    TOOL_OPT_END = 0, /* ends the table */
    TOOL_OPT_GROUP,   /* not an option: a heading in the help ("sampling:") */
    TOOL_OPT_FLAG,    /* no value: the int at `at` becomes 1 */
    TOOL_OPT_INT,     /* an integer in [lo, hi] into the int at `at` */
    TOOL_OPT_LONG,    /* an integer in [lo, hi] into the long at `at` */
    TOOL_OPT_U64,    /* a decimal integer in [0, hi] (hi 0: 2^64 - 1) into the unsigned long long */
    TOOL_OPT_DOUBLE, /* a finite number in [lo, hi] ((lo, hi] with open_lo) into the double */
    TOOL_OPT_FLOAT,  /* the same into the float at `at` */
    TOOL_OPT_STRING, /* a non-empty string into the const char * at `at` */
    TOOL_OPT_SIZE,   /* "WxH" into the ints at `at` and `at2`, each in [1, hi] (hi 0: INT_MAX) */
    TOOL_OPT_EXPOSURE, /* "auto" or stops in [-64, 64]: the float at `at`, the int at `at2` is
                        * 1 for auto, else 0 */
    TOOL_OPT_PARSE,    /* parse(value, field) != 0 accepts it (a name of the library's) */
    TOOL_OPT_CUSTOM,   /* handle(...) reads the value (a flag when metavar is NULL): cross-field */
} tool_opt_kind;

typedef struct tool_opt tool_opt;

/* A custom option: value is NULL when none was given (or for a flag); returns an exit code
 * (EXIT_OK when accepted). */
typedef int (*tool_opt_handler)(const char *cmd, const tool_opt *opt, const char *value, void *ctx);

struct tool_opt {
    tool_opt_kind kind;
    const char *name;     /* "--size" (GROUP: the heading) */
    const char *alias;    /* "-o", or NULL */
    const char *metavar;  /* "WxH"; NULL for a flag */
    const char *then;     /* FLAG: the arguments after it as the help shows them ("DIR...") */
    const char *help;     /* the help, lines broken with '\n' (joined in Markdown) */
    size_t at;            /* offsetof the field in the command's context (not CUSTOM) */
    size_t at2;           /* SIZE: the height's; EXPOSURE: the auto flag's */
    double lo, hi;        /* INT, LONG, DOUBLE, FLOAT: the range (both +-HUGE_VAL: none) */
    int open_lo, open_hi; /* DOUBLE, FLOAT: lo (hi) itself is refused */
    /* What the value must be, in the error "OPTION needs WHAT in [lo, hi], not 'V'": "a
     * count", "degrees" (numbers; default "a count" or "a number"), "a file" (STRING);
     * for PARSE the whole expectation, "must be clamp, reinhard or aces". */
    const char *what;
    int (*parse)(const char *value, void *field); /* PARSE */
    tool_opt_handler handle;                      /* CUSTOM */
    /* 1 + offsetof a const char * in the context that is set to the option's name when it
     * is given (0: none): what a later check names ("--exposure applies to PNG output"). */
    size_t note;
};

/* A command's options: its usage line(s), the prose above the options, the table, and
 * what takes the arguments that are not options. */
typedef struct tool_optspec {
    const char *cmd;   /* "sky", "luminaire create": in messages and headings */
    const char *usage; /* "usage: lumis sky [options] -o OUT" (may hold several lines) */
    const char *intro; /* paragraphs between the usage and the options, or NULL */
    const tool_opt *opts;
    /* An argument that is not an option (nor "-"-led): returns an exit code.  NULL: each
     * is refused as an unknown argument. */
    int (*positional)(const char *cmd, const char *arg, void *ctx);
    const char *outro; /* text after the options, or NULL */
} tool_optspec;

/* Reads argv[1..argc-1] into ctx by spec.  Returns -1 when the command is to go on, else an
 * exit code to return at once: EXIT_OK after --help (printed on stdout), EXIT_USAGE after
 * an error (printed on stderr, naming the option and the value). */
int tool_optparse(const tool_optspec *spec, int argc, char **argv, void *ctx);

/* The help generated from spec (what --help prints). */
void tool_opthelp(const tool_optspec *spec, FILE *f);

/* The options of spec as a Markdown section (docs/options.md). */
void tool_optmarkdown(const tool_optspec *spec, FILE *f);

/* 1 + offsetof(type, field): a tool_opt's note. */
#define TOOL_NOTE(type, field) (offsetof(type, field) + 1)

/* Parsers for TOOL_OPT_PARSE: a library's name into its enum. */
int tool_opt_tonemap(const char *value, void *field);
#define TOOL_TONEMAP_WHAT "must be clamp, reinhard or aces"

#endif
