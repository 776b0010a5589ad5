/* strands.c — the loader that picks a strand file reader by extension
   (strands_tfx.c, strands_hair.c; what they share is strands_common.c). */
#include <string.h>
#include <strings.h>

#include "errfmt.h"
#include <hairtier/strands.h>

static bool has_extension(const char *path, const char *ext) {
    size_t n = strlen(path), e = strlen(ext);
    return n > e && strcasecmp(path + n - e, ext) == 0;
}

ht_result ht_strands_load(const char *path, ht_strands *out, char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    if (has_extension(path, ".tfx")) return ht_strands_load_tfx(path, out, err, err_size);
    if (has_extension(path, ".hair")) return ht_strands_load_hair(path, out, err, err_size);
    ht_set_error(err, err_size, "%s: not a strand file: the name must end in .tfx (TressFX 4.0) or .hair", path);
    return HT_ERR_PARSE;
}
