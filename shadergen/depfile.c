/* depfile.c — see depfile.h. The spellings were tried against GNU make 4.3
   and ninja 1.11 (tests/test_depfile.c runs both): make and ninja read
   "\ ", "\#" and "\:" as the character and "$$" as "$"; a run of N
   backslashes before a space is written 2N (both halve it). Everything
   else below is read literally by both, or by neither. */
#include "depfile.h"

#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "errfmt.h"
#include "file_atomic.h"

/* Bytes both read literally in a rule: ninja's plain set, less what make
   treats as syntax there (';' '=' '%' '|'). */
static bool plain(unsigned char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c >= 0x80 ||
           strchr("+,/_.~()}{@[]!-", c) != NULL;
}

/* Why name has no common spelling (in why), or NULL. */
static const char *unspellable(const char *name, char why[64]) {
    if (!name[0]) return "an empty name";
    for (const char *p = name; *p; p++) {
        unsigned char c = (unsigned char)*p;
        if (plain(c) || c == ' ' || c == '#' || c == ':' || c == '$') continue;
        if (c == '\\') {
            size_t run = strspn(p, "\\");
            char next = p[run];
            if (next == '\0' || next == '#' || next == ':') return "a backslash before '#', ':' or the end";
            p += run - 1;
            continue;
        }
        if (c < 0x20 || c == 0x7f) snprintf(why, 64, "the control character 0x%02x", c);
        else snprintf(why, 64, "'%c' (make and ninja do not read it alike)", c);
        return why;
    }
    return NULL;
}

ht_result ht_depfile_check_name(const char *name, char *err, size_t err_size) {
    char buf[64];
    const char *why = unspellable(name, buf);
    if (!why) return HT_OK;
    return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: cannot be listed in a depfile (-MD, -MF): %s", name,
                   why);
}

ht_result ht_depfile_check_report(const char *dir, const ht_bundle_report *rep, char *err, size_t err_size) {
    ht_result r = ht_depfile_check_name(dir, err, err_size);
    for (int k = 0; k < rep->input_count && r == HT_OK; k++) r = ht_depfile_check_name(rep->inputs[k], err, err_size);
    return r;
}

static void put_path(FILE *f, const char *path) {
    for (const char *p = path; *p; p++) {
        if (*p == '\\') {
            size_t run = strspn(p, "\\");
            bool doubled = p[run] == ' ';
            for (size_t i = 0; i < (doubled ? 2 * run : run); i++) fputc('\\', f);
            p += run - 1;
            continue;
        }
        if (*p == ' ' || *p == '#' || *p == ':') fputc('\\', f);
        else if (*p == '$') fputc('$', f);
        fputc(*p, f);
    }
}

/* The running hairgen, when it can be named in a depfile: "" otherwise. */
static void self_path(char out[PATH_MAX]) {
    ssize_t n = readlink("/proc/self/exe", out, PATH_MAX - 1);
    struct stat st;
    char why[64];
    out[n > 0 ? n : 0] = '\0';
    if (n <= 0 || unspellable(out, why) || stat(out, &st) != 0 || !S_ISREG(st.st_mode)) out[0] = '\0';
}

typedef struct depfile_text {
    const ht_depfile_rule *rules;
    int count;
    const char *self;
} depfile_text;

static bool put_rules(FILE *f, void *ctx, char *why, size_t why_size) {
    (void)why, (void)why_size;
    const depfile_text *t = ctx;
    for (int i = 0; i < t->count; i++) {
        const ht_bundle_report *rep = t->rules[i].report;
        if (i) fputc('\n', f);
        put_path(f, t->rules[i].dir);
        fputs("/manifest.json:", f);
        for (int k = 0; k < rep->input_count; k++) {
            fputs(" \\\n  ", f);
            put_path(f, rep->inputs[k]);
        }
        if (t->self[0]) {
            fputs(" \\\n  ", f);
            put_path(f, t->self);
        }
        fputc('\n', f);
        /* As GCC's -MP: a deleted input rebuilds instead of stopping make. */
        for (int k = 0; k < rep->input_count; k++) {
            fputc('\n', f);
            put_path(f, rep->inputs[k]);
            fputs(":\n", f);
        }
        if (t->self[0]) {
            fputc('\n', f);
            put_path(f, t->self);
            fputs(":\n", f);
        }
    }
    return !ferror(f);
}

ht_result ht_depfile_write(const char *path, const ht_depfile_rule *rules, int count, char *err, size_t err_size) {
    for (int i = 0; i < count; i++) {
        ht_result r = ht_depfile_check_report(rules[i].dir, rules[i].report, err, err_size);
        if (r != HT_OK) return r;
    }
    char self[PATH_MAX];
    self_path(self);
    return ht_file_write_atomic(path, put_rules, &(depfile_text){ rules, count, self }, err, err_size);
}
