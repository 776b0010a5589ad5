#!/bin/sh
# header_examples.sh — every public header's usage example compiles (make
# test runs it). Each block that follows a comment line "Usage ...:" (its
# parenthesis may run over lines, up to the one ending in ":") in a
# header's top comment (its lines indented 7 spaces, up to the first line
# indented less) becomes the body of a function in a C11 file that includes
# only that header and <stdio.h>/<string.h>/<stdint.h>; the callbacks an
# example names (my_getproc, my_log) are declared before it. It must
# compile with -Wall -Wextra -Werror against include/ alone. (The examples
# are C: compound literals. tests/install_test.sh includes every header
# from C++.)
# export.h is a macro header with nothing to call and has no example.
set -eu
CC=${CC:-cc}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/hairtier-examples.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "header_examples: FAIL: $*" >&2; exit 1; }

count=0
for h in include/hairtier/*.h; do
  name=$(basename "$h" .h)
  [ "$name" = export ] && continue
  src=$tmp/$name.c
  # The examples of the header's first comment, each as a function body.
  awk -v header="$name" '
    /\*\// && !done { if (inblock) print "}"; done = 1 }
    done { next }
    inblock && /^       / { sub(/^       /, ""); print; next }
    inblock && /^ *$/ { print ""; next }
    inblock { print "}"; inblock = 0 }
    /Usage/ { pending = 1 }
    pending && /:[ \t]*$/ { n++; print "void " header "_example_" n "(void) {"; inblock = 1; pending = 0 }
  ' "$h" > "$tmp/$name.body"
  blocks=$(grep -c '_example_' "$tmp/$name.body" || true)
  [ "$blocks" -gt 0 ] || fail "$h has no usage example (a comment line \"Usage...:\" and code indented 7 spaces)"
  {
    echo "#include <stdint.h>"
    echo "#include <stdio.h>"
    echo "#include <string.h>"
    echo "#include <hairtier/$name.h>"
    echo "void *my_getproc(const char *name);"
    echo "void my_log(void *user, const char *line);"
    cat "$tmp/$name.body"
  } > "$src"
  $CC -std=c11 -Wall -Wextra -Werror -Wno-unused-function -Iinclude -c "$src" -o "$tmp/$name.o" ||
    fail "$h: its usage example does not compile as C11 (extracted to $src)"
  count=$((count + blocks))
done
echo "header_examples: $count usage examples of $(ls include/hairtier/*.h | wc -l) public headers compile as C11"
