/* cli.c — see cli.h. */
#include "cli.h"

#include <stdio.h>
#include <string.h>

#include "errfmt.h"

#ifndef HT_VERSION
#error "HT_VERSION: the Makefile passes its VERSION"
#endif

#define MAX_OPTIONS 48   /* a program's long options; the most today is 14 */
enum { KEY_VERSION = 1000 };

const char *cli_unexpected(const char *value) {
    static char message[240];
    snprintf(message, sizeof message, "%.200s: unexpected argument", value ? value : "(none)");
    return message;
}

const char *cli_take_nothing(void *user, int key, const char *value) {
    (void)user, (void)key;
    return cli_unexpected(value);
}

/* why may quote an argument: one line whatever it holds (errfmt.h). */
int cli_usage_error(const cli_program *p, const char *why) {
    ht_print_line(stderr, "%s: %s", p->name, why);
    fputs(p->synopsis, stderr);
    return 2;
}

int cli_parse(const cli_program *p, int argc, char **argv, cli_take_fn take, void *user) {
    struct option longs[MAX_OPTIONS + 3];
    int n = 0;
    for (const struct option *o = p->long_options; o && o->name && n < MAX_OPTIONS; o++) longs[n++] = *o;
    longs[n++] = (struct option){ "help", no_argument, NULL, 'h' };
    longs[n++] = (struct option){ "version", no_argument, NULL, KEY_VERSION };
    longs[n] = (struct option){ 0 };
    /* '-': operands come back in order as key 1; ':': a missing value is ':'. */
    char shorts[64];
    snprintf(shorts, sizeof shorts, "-:%sh", p->short_options ? p->short_options : "");
    opterr = 0;
    optind = 1;
    char why[320];
    for (;;) {
        int key = p->long_only ? getopt_long_only(argc, argv, shorts, longs, NULL)
                               : getopt_long(argc, argv, shorts, longs, NULL);
        if (key == -1) break;
        const char *arg = argv[optind - 1];
        if (key == 'h') {
            fputs(p->synopsis, stdout);
            if (p->help) fputs(p->help, stdout);
            return 0;
        }
        if (key == KEY_VERSION) {
            printf("%s (hairtier) %s\n", p->name, HT_VERSION);
            if (p->version_note) printf("%s\n", p->version_note);
            return 0;
        }
        if (key == '?' || key == ':') {
            /* a short option is named alone (it may sit in a group: "-qx") */
            char name[80];
            if (strncmp(arg, "--", 2) != 0 && !p->long_only && optopt > 0 && optopt < CLI_LONG_ONLY)
                snprintf(name, sizeof name, "-%c", optopt);
            else snprintf(name, sizeof name, "%.*s", (int)strcspn(arg, "="), arg);
            snprintf(why, sizeof why, "%.80s: %s", name,
                     key == ':' ? "missing value" : strchr(arg, '=') && optopt ? "takes no value" : "unknown option");
            return cli_usage_error(p, why);
        }
        const char *refused = take(user, key, optarg);
        if (refused) return cli_usage_error(p, refused);
    }
    for (int i = optind; i < argc; i++) {   /* after "--" */
        const char *refused = take(user, CLI_OPERAND, argv[i]);
        if (refused) return cli_usage_error(p, refused);
    }
    return CLI_RUN;
}
