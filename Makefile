# hairtier — `make` builds build/hairgen, build/hairview and build/libhairtier.a;
# `make test` runs every test; `make demo` renders the default scenes to out/;
# `make asan` runs the tests under AddressSanitizer + UBSan; `make bench`;
# `make fuzz` builds the libFuzzer targets (fuzz/, clang, ASan + UBSan) and
# runs each for FUZZ_SECONDS (60); `make fuzz-smoke` runs each for 5 s (CI);
# `make check-valgrind` runs make demo's programs under memcheck.
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
SOFTPIPE_TESTS := test_render_app_state test_render_marschner test_render_fixed test_render_fixed4 test_render_gl11 test_render_glsl_compile \
                  test_render_passes test_render_probe test_render_robustness test_render_scenes
$(foreach t,$(filter-out $(notdir $(TESTS)),$(SOFTPIPE_TESTS)),$(error SOFTPIPE_TESTS: no tests/$(t).c))
DEPS_STAMP := $(BUILD)/.deps-installed

.PHONY: all deps test asan bench demo clean fuzz fuzz-build fuzz-seeds fuzz-smoke check-valgrind
# Keep objects that pattern rules build on the way (tests, examples).
.SECONDARY:
.DEFAULT_GOAL := all

all: $(LIB) $(HAIRGEN) $(PROGRAMS)

# Installs the Debian packages of $(1) that are missing (apt-get, as root).
define install_missing
	@missing=""; for p in $(1); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "make: installing Debian packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null || exit 1; \
	fi
endef

deps: $(DEPS_STAMP)
$(DEPS_STAMP):
	$(call install_missing,$(DEB_PACKAGES))
	@mkdir -p $(dir $@) && touch $@

$(BUILD)/obj/%.o: %.c | $(DEPS_STAMP)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

# The gl11 tier's per-vertex shading loops: sqrtf inline and selects
# if-converted, so GCC's -O2 vectoriser takes them (neither flag changes a
# result; fallback/gl11_program.c says why).
# The per-vertex loops of the tiers that do CPU work (structure of arrays)
# vectorise only without errno from sqrtf and at -O3's cost model; neither
# flag changes a result.
$(BUILD)/obj/fallback/gl11_program.o: CFLAGS += -fno-math-errno -fno-trapping-math
$(BUILD)/obj/fallback/fixed_soa.o $(BUILD)/obj/fallback/fixed4_program.o: CFLAGS += -O3 -fno-math-errno -fno-trapping-math

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

# Every benchmark on llvmpipe, then the frame benchmark again on softpipe
# (an interpreter: a stand-in for a slow fragment unit), smaller so it ends.
bench: all
	@for b in $(filter $(BUILD)/bench_%,$(PROGRAMS)); do echo "== $$b (llvmpipe)"; $$b || exit 1; done
	@echo "== $(BUILD)/bench_frame --hairs 2000 --size 256 --frames 3 (softpipe)"
	@GALLIUM_DRIVER=softpipe $(BUILD)/bench_frame --hairs 2000 --size 256 --frames 3

demo: all
	@mkdir -p out
	@for scene in furball patches; do \
	  echo "== $$scene: hairgen materials/dark-brown.json --scene scenes/$$scene.json -o out/$$scene-bundle"; \
	  $(HAIRGEN) materials/dark-brown.json --scene scenes/$$scene.json -o out/$$scene-bundle || exit 1; \
	  echo "== $$scene: hairview --bundle out/$$scene-bundle --scene scenes/$$scene.json -o out/$$scene.png"; \
	  $(BUILD)/hairview --bundle out/$$scene-bundle --scene scenes/$$scene.json -o out/$$scene.png || exit 1; \
	done
	@echo "== backlit: hairgen materials/brown-marschner.json --scene scenes/backlit.json -o out/backlit-bundle"
	@$(HAIRGEN) materials/brown-marschner.json --scene scenes/backlit.json -o out/backlit-bundle
	@echo "== backlit: hairview --bundle out/backlit-bundle --scene scenes/backlit.json -o out/backlit.png"
	@$(BUILD)/hairview --bundle out/backlit-bundle --scene scenes/backlit.json -o out/backlit.png
	@echo "demo: wrote out/furball.png, out/patches.png and out/backlit.png (the marschner tier lit from behind; bundles in out/*-bundle)"

# ---- fuzzing (docs/robustness.md records the runs) ----
FUZZ_BUILD   ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := $(patsubst fuzz/%.c,%,$(wildcard fuzz/fuzz_*.c))
FUZZ_SAN     := -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined

$(BUILD)/fuzz/%: $(BUILD)/obj/fuzz/%.o $(GENLIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) -fsanitize=fuzzer $^ $(LDLIBS) -o $@

# libFuzzer needs clang and its runtime (compiler-rt), installed like the rest.
FUZZ_DEB_PACKAGES := clang libclang-rt-14-dev

fuzz-build: deps
	$(call install_missing,$(FUZZ_DEB_PACKAGES))
	$(MAKE) BUILD=$(FUZZ_BUILD) CC=clang OPT="-O1 -g -fno-omit-frame-pointer" SAN="$(FUZZ_SAN)" \
	  $(patsubst %,$(FUZZ_BUILD)/fuzz/%,$(FUZZ_TARGETS))

# Seeds: the shipped materials and scenes, a generated bundle's manifest,
# combiner program and PNGs; each target's corpus grows in $(FUZZ_BUILD)/corpus.
fuzz-seeds: $(HAIRGEN)
	@rm -rf $(FUZZ_BUILD)/seeds && mkdir -p $(FUZZ_BUILD)/seeds/fuzz_material $(FUZZ_BUILD)/seeds/fuzz_scene \
	  $(FUZZ_BUILD)/seeds/fuzz_manifest $(FUZZ_BUILD)/seeds/fuzz_combiner $(FUZZ_BUILD)/seeds/fuzz_png \
	  $(FUZZ_BUILD)/seeds/fuzz_json $(FUZZ_BUILD)/seeds/fuzz_fixed4 $(FUZZ_BUILD)/seeds/fuzz_gl11
	@$(HAIRGEN) materials/dark-brown.json --scene scenes/furball.json -o $(FUZZ_BUILD)/seed-bundle >/dev/null
	@$(HAIRGEN) materials/kajiya-kay.json -o $(FUZZ_BUILD)/seed-bundle-kk >/dev/null
	@cp materials/*.json $(FUZZ_BUILD)/seeds/fuzz_material/
	@cp scenes/*.json $(FUZZ_BUILD)/seeds/fuzz_scene/
	@cp $(FUZZ_BUILD)/seed-bundle/manifest.json $(FUZZ_BUILD)/seeds/fuzz_manifest/a.json
	@cp $(FUZZ_BUILD)/seed-bundle-kk/manifest.json $(FUZZ_BUILD)/seeds/fuzz_manifest/b.json
	@cp $(FUZZ_BUILD)/seed-bundle/fixed.json $(FUZZ_BUILD)/seeds/fuzz_combiner/a.json
	@cp $(FUZZ_BUILD)/seed-bundle-kk/fixed.json $(FUZZ_BUILD)/seeds/fuzz_combiner/b.json
	@cp $(FUZZ_BUILD)/seed-bundle/fixed4.json $(FUZZ_BUILD)/seeds/fuzz_fixed4/a.json
	@cp $(FUZZ_BUILD)/seed-bundle-kk/fixed4.json $(FUZZ_BUILD)/seeds/fuzz_fixed4/b.json
	@cp $(FUZZ_BUILD)/seed-bundle/gl11.json $(FUZZ_BUILD)/seeds/fuzz_gl11/a.json
	@cp $(FUZZ_BUILD)/seed-bundle-kk/gl11.json $(FUZZ_BUILD)/seeds/fuzz_gl11/b.json
	@cp $(FUZZ_BUILD)/seed-bundle/detail.png $(FUZZ_BUILD)/seeds/fuzz_png/detail.png
	@find tests/data -name '*.png' -size -64k -exec cp {} $(FUZZ_BUILD)/seeds/fuzz_png/ \; 2>/dev/null || true
	@cp materials/*.json scenes/*.json $(FUZZ_BUILD)/seed-bundle/*.json $(FUZZ_BUILD)/seeds/fuzz_json/

# Each target for FUZZ_SECONDS; its last lines (runs, coverage, any crash)
# go to $(FUZZ_BUILD)/TARGET.log, a summary line per target to stdout.
fuzz: fuzz-build fuzz-seeds
	@fail=0; for t in $(FUZZ_TARGETS); do \
	  mkdir -p $(FUZZ_BUILD)/corpus/$$t $(FUZZ_BUILD)/crashes/$$t; \
	  if $(FUZZ_BUILD)/fuzz/$$t -max_total_time=$(FUZZ_SECONDS) -rss_limit_mb=2048 -timeout=10 -max_len=65536 \
	       -print_final_stats=1 -artifact_prefix=$(FUZZ_BUILD)/crashes/$$t/ \
	       $(FUZZ_BUILD)/corpus/$$t $(FUZZ_BUILD)/seeds/$$t > $(FUZZ_BUILD)/$$t.log 2>&1; then r=ok; \
	  else r=FAILED; fail=1; fi; \
	  echo "$$t: $$r, $$(grep -o 'stat::number_of_executed_units: *[0-9]*' $(FUZZ_BUILD)/$$t.log | grep -o '[0-9]*$$') runs in $(FUZZ_SECONDS) s, corpus $$(ls $(FUZZ_BUILD)/corpus/$$t | wc -l), $$(grep -o 'cov: [0-9]*' $(FUZZ_BUILD)/$$t.log | tail -1)"; \
	done; rm -f /tmp/hairtier-fuzz-png-*.png; [ $$fail -eq 0 ]

fuzz-smoke:
	$(MAKE) fuzz FUZZ_SECONDS=5

# ---- valgrind memcheck over make demo's programs (a small scene) ----
VALGRIND := valgrind --tool=memcheck --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
            --suppressions=tests/valgrind.supp --num-callers=30
check-valgrind: all
	@mkdir -p out/valgrind
	$(VALGRIND) $(HAIRGEN) materials/dark-brown.json --scene tests/data/valgrind-scene.json -o out/valgrind/bundle
	MESA_SHADER_CACHE_DISABLE=true $(VALGRIND) $(BUILD)/hairview --bundle out/valgrind/bundle \
	  --scene tests/data/valgrind-scene.json -o out/valgrind/furball.png
	@echo "check-valgrind: clean"

clean:
	rm -rf build build-asan build-fuzz out

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
