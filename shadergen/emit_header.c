/* emit_header.c — a generated bundle as one C header (hairgen
   --emit-header; hairgen.h has the API). Every file goes in as the bytes a
   bundle directory holds, PNG textures included: compressed (the dark-brown
   furball bundle's three PNGs are 127 843 bytes against 1 310 720 bytes of
   texels, 10 times less in the program), and read back by
   the runtime through the very decoder and checks a directory's files go
   through (runtime/io/bundle_source.c), so a header is exactly a directory in
   another place. Bytes are decimal array initialisers, not string literals:
   C99 promises only 4095 characters in one literal (-pedantic warns past
   it) and a text may hold any byte. The text depends only on the bundle
   and the symbol: no date, no path. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "errfmt.h"
#include "file_atomic.h"
#include <hairtier/hairgen.h>
#include "hairgen_internal.h"
#include "strbuf.h"

/* Bytes per line of an array initialiser (lines stay under 100 columns). */
#define BYTES_PER_LINE 20

ht_result ht_generated_file_bytes(const ht_generated_file *f, unsigned char **data, size_t *size, char *err,
                                  size_t err_size) {
    *data = NULL;
    *size = 0;
    if (f->text) {
        size_t n = strlen(f->text);
        unsigned char *copy = malloc(n ? n : 1);
        if (!copy) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", f->name);
        memcpy(copy, f->text, n);
        *data = copy;
        *size = n;
        return HT_OK;
    }
    if (f->png) {
        *data = malloc(f->png_size ? f->png_size : 1);
        if (!*data) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", f->name);
        memcpy(*data, f->png, f->png_size);
        *size = f->png_size;
        return HT_OK;
    }
    ht_result r = ht_png_encode(&f->image, data, size);
    if (r == HT_ERR_OUT_OF_MEMORY) return ht_fail(err, err_size, r, "%s: out of memory", f->name);
    if (r != HT_OK) return ht_fail(err, err_size, r, "%s: not an image a PNG can hold", f->name);
    return HT_OK;
}

/* C11 and C++17 keywords (and C's alternative spellings C++ reserves): a
   symbol named like one would not compile in one of the two. */
static const char *const keywords[] = {
    "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break", "case", "catch",
    "char", "char16_t", "char32_t", "class", "compl", "const", "const_cast", "constexpr", "continue",
    "decltype", "default", "delete", "do", "double", "dynamic_cast", "else", "enum", "explicit", "export",
    "extern", "false", "float", "for", "friend", "goto", "if", "inline", "int", "long", "mutable", "namespace",
    "new", "noexcept", "not", "not_eq", "nullptr", "operator", "or", "or_eq", "private", "protected", "public",
    "register", "reinterpret_cast", "restrict", "return", "short", "signed", "sizeof", "static",
    "static_assert", "static_cast", "struct", "switch", "template", "this", "thread_local", "throw", "true",
    "try", "typedef", "typeid", "typename", "union", "unsigned", "using", "virtual", "void", "volatile",
    "wchar_t", "while", "xor", "xor_eq", NULL
};

/* Why symbol (and SYMBOL_files, SYMBOL_fN, which the header also
   defines) could name what the headers it includes define, or NULL. The
   header includes hairtier.h, which includes stdbool.h, stddef.h and
   stdint.h: their macros are all capitals (NULL, SIZE_MAX, INT8_C), their
   types end in _t (size_t, uint8_t), offsetof is the one lowercase macro,
   and hairtier's own names start with ht_ or HT_. A rule by shape, not a
   list of today's names, so a name added to hairtier.h cannot collide. */
static const char *colliding(const char *symbol) {
    if ((symbol[0] == 'h' || symbol[0] == 'H') && (symbol[1] == 't' || symbol[1] == 'T') &&
        (symbol[2] == '_' || symbol[2] == '\0'))
        return "ht_ and HT_ are hairtier's own names (ht_bundle_memory, HT_OK)";
    bool lower = false;
    for (const char *p = symbol; *p; p++) lower = lower || (*p >= 'a' && *p <= 'z');
    if (!lower) return "no lower-case letter: all-capital names are the standard headers' macros (NULL, SIZE_MAX)";
    size_t n = strlen(symbol);
    if (n >= 2 && strcmp(symbol + n - 2, "_t") == 0) return "a _t suffix names types (size_t, uint8_t)";
    if (strcmp(symbol, "offsetof") == 0) return "a macro of stddef.h";
    if (strcmp(symbol, "std") == 0) return "C++'s standard namespace";
    return NULL;
}

static bool ident_char(char c, bool first) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || (!first && c >= '0' && c <= '9');
}

ht_result ht_header_symbol_check(const char *symbol, char *err, size_t err_size) {
    if (!symbol || !symbol[0])
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "--header-symbol: empty");
    size_t n = strlen(symbol);
    if (n > HT_HEADER_SYMBOL_MAX)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "--header-symbol: %.60s...: %zu bytes, at most %d",
                       symbol, n, HT_HEADER_SYMBOL_MAX);
    for (size_t i = 0; i < n; i++)
        if (!ident_char(symbol[i], i == 0))
            return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "--header-symbol: \"%s\": not a C identifier "
                           "(letters, digits and _, not starting with a digit)", symbol);
    if (symbol[0] == '_')
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "--header-symbol: \"%s\": a leading _ is "
                       "reserved to the implementation", symbol);
    for (int i = 0; keywords[i]; i++)
        if (strcmp(symbol, keywords[i]) == 0)
            return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "--header-symbol: \"%s\": a C or C++ keyword",
                           symbol);
    const char *why = colliding(symbol);
    if (why) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "--header-symbol: \"%s\": %s", symbol, why);
    return HT_OK;
}

void ht_header_symbol_default(const char *material_name, char out[HT_HEADER_SYMBOL_MAX + 1]) {
    static const char suffix[] = "_bundle";
    const size_t room = HT_HEADER_SYMBOL_MAX - (sizeof suffix - 1);
    size_t n = 0;
    /* A name starting with a digit or _ (or none at all) gets a prefix so
       the symbol is an identifier outside the reserved space. */
    const char *name = material_name ? material_name : "";
    if (!ident_char(name[0], true) || name[0] == '_') n = (size_t)snprintf(out, room + 1, "hair");
    /* A name hairtier's own (ht_...) gets a prefix too, so that the
       default always passes ht_header_symbol_check. */
    if (n == 0 && (name[0] == 'h' || name[0] == 'H') && (name[1] == 't' || name[1] == 'T') &&
        (name[2] == '_' || !ident_char(name[2], false)))
        n = (size_t)snprintf(out, room + 1, "hair_");
    for (const char *p = name; *p && n < room; p++) out[n++] = ident_char(*p, false) ? *p : '_';
    memcpy(out + n, suffix, sizeof suffix);
}

/* A material name shown in the header's comment: bytes that could end the
   comment or the line ("*" "/", control bytes, non-ASCII) become '?'. */
static void comment_safe(const char *name, char *out, size_t size) {
    size_t n = 0;
    for (const char *p = name ? name : ""; *p && n + 1 < size; p++) {
        unsigned char c = (unsigned char)*p;
        out[n++] = (c < 0x20 || c > 0x7e || c == '*' || c == '/' || c == '\\') ? '?' : (char)c;
    }
    out[n] = '\0';
}

/* One array initialiser: the bytes, BYTES_PER_LINE to a line. */
static void add_bytes(ht_strbuf *sb, const unsigned char *data, size_t size) {
    char line[BYTES_PER_LINE * 4 + 8];
    for (size_t i = 0; i < size; i += BYTES_PER_LINE) {
        size_t len = 0;
        line[len++] = ' ';
        line[len++] = ' ';
        line[len++] = ' ';
        line[len++] = ' ';
        for (size_t k = i; k < size && k < i + BYTES_PER_LINE; k++) {
            unsigned v = data[k];
            if (v >= 100) line[len++] = (char)('0' + v / 100);
            if (v >= 10) line[len++] = (char)('0' + v / 10 % 10);
            line[len++] = (char)('0' + v % 10);
            line[len++] = ',';
        }
        line[len++] = '\n';
        line[len] = '\0';
        ht_strbuf_add(sb, line);
    }
}

/* The file name as a C string literal: printable ASCII but " and \. */
static void add_name_literal(ht_strbuf *sb, const char *name) {
    ht_strbuf_add(sb, "\"");
    for (const char *p = name; *p; p++) {
        unsigned char c = (unsigned char)*p;
        if (c == '"' || c == '\\' || c < 0x20 || c > 0x7e) ht_strbuf_addf(sb, "\\%03o", c);
        else ht_strbuf_addf(sb, "%c", c);
    }
    ht_strbuf_add(sb, "\"");
}

ht_result ht_bundle_header_text(const ht_generated *g, const char *material_name, const char *symbol,
                                char **text, char *err, size_t err_size) {
    *text = NULL;
    if (!g || g->file_count < 1 || g->file_count > HT_GENERATED_MAX_FILES)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "ht_bundle_header_text: no generated bundle");
    char sym[HT_HEADER_SYMBOL_MAX + 1];
    if (symbol) {
        ht_result r = ht_header_symbol_check(symbol, err, err_size);
        if (r != HT_OK) return r;
        snprintf(sym, sizeof sym, "%s", symbol);
    } else {
        ht_header_symbol_default(material_name, sym);
    }
    char guard[HT_HEADER_SYMBOL_MAX + 32];
    int gn = snprintf(guard, sizeof guard, "HAIRTIER_BUNDLE_%s_H", sym);
    for (int i = 0; i < gn; i++)
        if (guard[i] >= 'a' && guard[i] <= 'z') guard[i] = (char)(guard[i] - 'a' + 'A');

    unsigned char *data[HT_GENERATED_MAX_FILES] = { 0 };
    size_t size[HT_GENERATED_MAX_FILES] = { 0 };
    ht_result r = HT_OK;
    for (int i = 0; i < g->file_count && r == HT_OK; i++)
        r = ht_generated_file_bytes(&g->files[i], &data[i], &size[i], err, err_size);

    ht_strbuf sb;
    ht_strbuf_init(&sb);
    if (r == HT_OK) {
        char shown[64];
        comment_safe(material_name, shown, sizeof shown);
        ht_strbuf_addf(&sb, "/* hairtier bundle %s: written by hairgen --emit-header; do not edit.\n", sym);
        ht_strbuf_addf(&sb, "   Material \"%s\" (input_hash %016llx): the bundle's %d files byte for byte\n",
                       shown, (unsigned long long)g->input_hash, g->file_count);
        ht_strbuf_addf(&sb, "   as hairgen -o DIR writes them (PNG textures stay PNG), and one entry.\n"
                            "   Include this header (it includes hairtier.h) and hand the entry over:\n\n"
                            "       ht_renderer_create(&(ht_renderer_desc){ .getproc = getproc,\n"
                            "                              .bundle_memory = &%s }, &renderer);\n\n"
                            "   Files:\n", sym);
        for (int i = 0; i < g->file_count; i++)
            ht_strbuf_addf(&sb, "       %-20s %8zu bytes\n", g->files[i].name, size[i]);
        ht_strbuf_addf(&sb, "*/\n#ifndef %s\n#define %s\n\n#include <hairtier/hairtier.h>\n\n", guard, guard);
        for (int i = 0; i < g->file_count; i++) {
            if (!size[i]) continue; /* a zero-length array is not C; the entry says NULL, 0 */
            ht_strbuf_addf(&sb, "/* %s */\nstatic const unsigned char %s_f%d[%zu] = {\n", g->files[i].name, sym, i,
                           size[i]);
            add_bytes(&sb, data[i], size[i]);
            ht_strbuf_add(&sb, "};\n\n");
        }
        ht_strbuf_addf(&sb, "static const ht_bundle_file %s_files[%d] = {\n", sym, g->file_count);
        for (int i = 0; i < g->file_count; i++) {
            ht_strbuf_add(&sb, "    { ");
            add_name_literal(&sb, g->files[i].name);
            if (size[i]) ht_strbuf_addf(&sb, ", %s_f%d, %zu },\n", sym, i, size[i]);
            else ht_strbuf_add(&sb, ", 0, 0 },\n");
        }
        ht_strbuf_addf(&sb, "};\n\nstatic const ht_bundle_memory %s = { \"%s\", %s_files, %d };\n\n#endif\n", sym,
                       sym, sym, g->file_count);
        *text = ht_strbuf_take(&sb);
        if (!*text) r = ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory writing the header", sym);
    }
    ht_strbuf_free(&sb);
    for (int i = 0; i < g->file_count; i++) free(data[i]);
    return r;
}

static bool put_text(FILE *f, void *ctx, char *why, size_t why_size) {
    (void)why, (void)why_size;
    const char *text = ctx;
    size_t len = strlen(text);
    return fwrite(text, 1, len, f) == len;
}

ht_result ht_bundle_header_write(const ht_generated *g, const char *material_name, const char *symbol,
                                 const char *path, char *err, size_t err_size) {
    if (!path || !path[0]) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "--emit-header: no path");
    char *text;
    ht_result r = ht_bundle_header_text(g, material_name, symbol, &text, err, err_size);
    if (r != HT_OK) return r;
    /* Whole or not at all, never over a device or a FIFO (file_atomic.h). */
    r = ht_file_write_atomic(path, put_text, text, err, err_size);
    free(text);
    return r;
}
