/* cli.h — the one command-line parser of every program (hairgen and the
   programs in examples/): getopt_long over the program's options, plus
   --help (-h), which prints the synopsis and help on stdout, and --version,
   which prints "NAME (hairtier) VERSION" (the Makefile's VERSION, passed
   to cli.c alone as HT_VERSION); an unknown option, a missing or
   bad value is one line "NAME: WHY" and the synopsis on stderr, exit 2.

   Usage:
       static const struct option longs[] = { { "scene", required_argument, NULL, 's' }, { 0 } };
       static const cli_program program = { .name = "prog", .synopsis = "usage: prog --scene S -o OUT\n",
                                            .help = "...\n", .short_options = "o:", .long_options = longs };
       static const char *take(void *user, int key, const char *value) {  // NULL, or why value is refused
           ... key: 's', 'o', or CLI_OPERAND for a word that is not an option ...
       }
       int rc = cli_parse(&program, argc, argv, take, &opts);
       if (rc != CLI_RUN) return rc;                  // 0 after --help / --version, 2 after an error
       if (!opts.out) return cli_usage_error(&program, "-o: required"); */
#ifndef HT_PLATFORM_CLI_H
#define HT_PLATFORM_CLI_H

#include <getopt.h>
#include <stdbool.h>

#define CLI_RUN (-1)     /* cli_parse: every option taken, the program runs */
#define CLI_OPERAND 1    /* the key of a word that is not an option, in order */
#define CLI_LONG_ONLY 256 /* keys from here up: long options without a short form */
/* A number macro as text, for a help string: CLI_STR(MAX_FRAMES). */
#define CLI_STR_(x) #x
#define CLI_STR(x) CLI_STR_(x)

typedef struct cli_program {
    const char *name;          /* what every line starts with: "hairview" */
    const char *synopsis;      /* "usage: ...\n" lines: on --help and after every usage error */
    const char *help;          /* NULL, or what --help prints after the synopsis */
    const char *version_note;  /* NULL, or a line --version prints after the version */
    const char *short_options; /* getopt's ("o:qj:"), without the leading '-' or ':' */
    const struct option *long_options; /* { 0 }-ended; --help and --version are added */
    bool long_only;            /* long options after one dash too ("-MD"; getopt_long_only) */
} cli_program;

/* NULL when the option (or operand) is taken, else why not: one line
   without the program's name ("--frames: expected an integer in 1..100"). */
typedef const char *(*cli_take_fn)(void *user, int key, const char *value);

/* CLI_RUN, 0 (--help or --version printed) or 2 (a usage error printed). */
int cli_parse(const cli_program *p, int argc, char **argv, cli_take_fn take, void *user);
/* "NAME: why" and the synopsis on stderr; returns 2, the usage exit status. */
int cli_usage_error(const cli_program *p, const char *why);
/* "VALUE: unexpected argument" (static storage): what a cli_take_fn
   returns for an operand or key it does not take. */
const char *cli_unexpected(const char *value);
/* The cli_take_fn of a program that takes no operand and no option of its
   own (--help and --version only). */
const char *cli_take_nothing(void *user, int key, const char *value);

#endif
