# hairtier — `make` builds build/hairgen, build/hairview and build/libhairtier.a;
# `make test` runs every test; `make demo` renders the default scenes to out/;
# `make asan` runs the tests under AddressSanitizer + UBSan; `make bench`.
# Missing Debian packages are installed first (apt-get, as root).

CC      ?= cc
BUILD   ?= build
OPT     ?= -O2 -g
SAN     ?=
WERROR  ?= -Werror

DEB_PACKAGES := libosmesa6-dev glslang-dev glslang-tools libcjson-dev libpng-dev \
                libcmocka-dev pkg-config

CPPFLAGS += -Iruntime -Ishadergen -Ifallback -I/usr/include/cjson -I/usr/include/libpng16
CFLAGS   += -std=c11 -D_DEFAULT_SOURCE -Wall -Wextra $(WERROR) $(OPT) $(SAN) -MMD -MP
LDFLAGS  += $(SAN)
# glslang's static libraries are C++; its pkg-config file is read lazily,
# after the packages are installed.
GLSLANG_LIBS = $(shell pkg-config --libs glslang) -lglslang-default-resource-limits -lstdc++
RUNTIME_LIBS = -lOSMesa -lcjson -lpng16 -lz -lpthread -lm
LDLIBS   = $(GLSLANG_LIBS) $(RUNTIME_LIBS)

RUNTIME_SRC := $(wildcard runtime/*.c fallback/*.c)
GEN_SRC     := $(filter-out shadergen/hairgen.c,$(wildcard shadergen/*.c))
TEST_SRC    := $(wildcard tests/test_*.c)
TEST_SUPPORT_SRC := $(wildcard tests/support_*.c)
EXAMPLE_SRC := $(wildcard examples/*.c)

obj = $(patsubst %.c,$(BUILD)/obj/%.o,$(1))

LIB       := $(BUILD)/libhairtier.a
GENLIB    := $(BUILD)/libhairgen.a
HAIRGEN   := $(BUILD)/hairgen
PROGRAMS  := $(patsubst examples/%.c,$(BUILD)/%,$(EXAMPLE_SRC))
TESTS     := $(patsubst tests/%.c,$(BUILD)/tests/%,$(TEST_SRC))
# Tests that render and so run a second time on softpipe (GALLIUM_DRIVER=
# softpipe), Mesa's second driver; every test runs on llvmpipe.
SOFTPIPE_TESTS := test_render_app_state test_render_fixed test_render_gl11 test_render_glsl_compile \
                  test_render_passes test_render_probe test_render_robustness test_render_scenes
$(foreach t,$(filter-out $(notdir $(TESTS)),$(SOFTPIPE_TESTS)),$(error SOFTPIPE_TESTS: no tests/$(t).c))
DEPS_STAMP := $(BUILD)/.deps-installed

.PHONY: all deps test asan bench demo clean
# Keep objects that pattern rules build on the way (tests, examples).
.SECONDARY:
.DEFAULT_GOAL := all

all: $(LIB) $(HAIRGEN) $(PROGRAMS)

deps: $(DEPS_STAMP)
$(DEPS_STAMP):
	@missing=""; for p in $(DEB_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "make: installing Debian packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null || exit 1; \
	fi
	@mkdir -p $(dir $@) && touch $@

$(BUILD)/obj/%.o: %.c | $(DEPS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

# The gl11 tier's per-vertex shading loops: sqrtf inline and selects
# if-converted, so GCC's -O2 vectoriser takes them (neither flag changes a
# result; fallback/gl11_program.c says why).
$(BUILD)/obj/fallback/gl11_program.o: CFLAGS += -fno-math-errno -fno-trapping-math

$(LIB): $(call obj,$(RUNTIME_SRC))
	@rm -f $@
	ar rcs $@ $^

$(GENLIB): $(call obj,$(GEN_SRC))
	@rm -f $@
	ar rcs $@ $^

$(HAIRGEN): $(call obj,shadergen/hairgen.c) $(GENLIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

# hairview draws a bundle: the runtime only, no generator, no glslang.
$(BUILD)/hairview: $(BUILD)/obj/examples/hairview.o $(LIB)
	$(CC) $(LDFLAGS) $^ $(RUNTIME_LIBS) -o $@

$(BUILD)/%: $(BUILD)/obj/examples/%.o $(GENLIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/tests/%: $(BUILD)/obj/tests/%.o $(call obj,$(TEST_SUPPORT_SRC)) $(GENLIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -lcmocka -o $@

# Every test binary runs from the repository root, on llvmpipe; those in
# SOFTPIPE_TESTS run again on softpipe.
test: all $(TESTS)
	@pass=0; fail=0; failed=""; \
	for t in $(TESTS); do \
	  for driver in llvmpipe softpipe; do \
	    case " $(SOFTPIPE_TESTS) " in *" $$(basename $$t) "*) ;; *) [ $$driver = softpipe ] && continue;; esac; \
	    echo "== $$t ($$driver)"; \
	    if GALLIUM_DRIVER=$$driver HAIRTIER_BUILD=$(BUILD) $$t; then pass=$$((pass+1)); \
	    else fail=$$((fail+1)); failed="$$failed $$t($$driver)"; fi; \
	  done; \
	done; \
	echo; [ -z "$$failed" ] || echo "failed:$$failed"; \
	echo "binaries: $$pass passed, $$fail failed"; \
	[ $$fail -eq 0 ]

asan:
	LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 \
	$(MAKE) BUILD=build-asan OPT="-O1 -g -fno-omit-frame-pointer" \
	  SAN="-fsanitize=address,undefined -fno-sanitize-recover=undefined" test

bench: all
	@for b in $(filter $(BUILD)/bench_%,$(PROGRAMS)); do echo "== $$b"; $$b || exit 1; done

demo: all
	@mkdir -p out
	@for scene in furball patches; do \
	  echo "== $$scene: hairgen materials/dark-brown.json --scene scenes/$$scene.json -o out/$$scene-bundle"; \
	  $(HAIRGEN) materials/dark-brown.json --scene scenes/$$scene.json -o out/$$scene-bundle || exit 1; \
	  echo "== $$scene: hairview --bundle out/$$scene-bundle --scene scenes/$$scene.json -o out/$$scene.png"; \
	  $(BUILD)/hairview --bundle out/$$scene-bundle --scene scenes/$$scene.json -o out/$$scene.png || exit 1; \
	done
	@echo "demo: wrote out/furball.png and out/patches.png (bundles in out/furball-bundle, out/patches-bundle)"

clean:
	rm -rf build build-asan out

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
