# hairtier — `make` builds build/hairgen, build/hairview and build/libhairtier.a;
# `make test` runs every test; `make accuracy` the accuracy sweep at the
# shipped sizes; `make demo` renders the shipped scenes to out/ (and one on
# GL ES 2.0);
# `make asan` runs the tests under AddressSanitizer + UBSan; `make bench`
# writes bench/results.{csv,md,svg} and bench/scaling.svg;
# `make fuzz` builds the libFuzzer targets (fuzz/, clang, ASan + UBSan) and
# runs each for FUZZ_SECONDS (60); `make fuzz-smoke` runs each for 5 s (CI);
# `make check-valgrind` runs make demo's programs under memcheck;
# `make report-check` opens haircompare's report in headless Chromium.
# Missing Debian packages are installed first (apt-get, as root).

CC      ?= cc
BUILD   ?= build
OPT     ?= -O2 -g
SAN     ?=
WERROR  ?= -Werror

# g++: the bundle header's C++ compile check (tests/data/header_use.c);
# cmake: the install test's find_package(hairtier) consumer.
# libdeflate-dev: the generator's PNG encoder (shadergen/png_encode.c says why).
# ninja-build: the depfile test reads hairgen's depfiles back with ninja (tests/test_depfile.c).
DEB_PACKAGES := libosmesa6-dev libegl-dev libegl-mesa0 glslang-dev glslang-tools libcjson-dev libpng-dev \
                libdeflate-dev libcmocka-dev pkg-config g++ cmake ninja-build

CPPFLAGS += -Iinclude -Iruntime/io -Iruntime/shading -Iruntime/mesh -Iruntime/render -Ishadergen -Ifallback -Iplatform -I/usr/include/cjson -I/usr/include/libpng16
CFLAGS   += -std=c11 -D_DEFAULT_SOURCE -Wall -Wextra $(WERROR) $(OPT) $(SAN) -MMD -MP
LDFLAGS  += $(SAN)
# gold links the tests and programs (static glslang) about three times faster than bfd.
LD_GOLD  := $(if $(shell command -v ld.gold 2>/dev/null),-fuse-ld=gold)
LDFLAGS  += $(LD_GOLD)
# glslang's static libraries are C++; its pkg-config file is read lazily,
# after the packages are installed.
GLSLANG_LIBS = $(shell pkg-config --libs glslang) -lglslang-default-resource-limits -lstdc++
# What libhairgen needs beyond libhairtier and glslang.
GEN_LIBS     = -ldeflate
CORE_LIBS    = -lcjson -lpng16 -lz -lpthread -lm
RUNTIME_LIBS = -lOSMesa $(CORE_LIBS)
# The offscreen context module (platform/offscreen.h) loads EGL and OSMesa
# with dlopen, so its programs start where there is no OSMesa.
OFFSCREEN_LIBS = -ldl
LDLIBS   = $(GLSLANG_LIBS) $(GEN_LIBS) $(RUNTIME_LIBS)

RUNTIME_SRC := $(wildcard runtime/*/*.c runtime/*.c fallback/*.c)
GEN_SRC     := $(filter-out shadergen/hairgen.c,$(wildcard shadergen/*.c))
# glslang's one-pass parse is C++ only (shadergen/glsl_parse.cpp says why).
GEN_CXX_SRC := $(wildcard shadergen/*.cpp)
TEST_SRC    := $(wildcard tests/test_*.c)
TEST_SUPPORT_SRC := $(wildcard tests/support_*.c)
# What every program shares, hairgen included (platform/: the offscreen
# context module and the command-line parser); the drawing programs' options.
PLATFORM_SRC := $(wildcard platform/*.c)
EXAMPLE_SHARED_SRC := examples/view_args.c
EXAMPLE_SRC := $(filter-out $(EXAMPLE_SHARED_SRC),$(wildcard examples/*.c))
# What the example programs share (tier rendering, the report's pieces in
# examples/compare/; the benchmarks' results files, plots and progress in
# examples/bench/; the offscreen context module): one archive they and the
# tests link.
EXAMPLE_LIB_SRC := $(wildcard examples/compare/*.c examples/bench/*.c) $(EXAMPLE_SHARED_SRC)

obj = $(patsubst %.c,$(BUILD)/obj/%.o,$(1))

LIB       := $(BUILD)/libhairtier.a
GENLIB    := $(BUILD)/libhairgen.a
# The shared libraries: soname libNAME.so.$(SOVERSION), only HT_API exported.
VERSION   := 0.1
SOVERSION := 0
SHLIB     := $(BUILD)/lib/libhairtier.so.$(VERSION)
GENSHLIB  := $(BUILD)/lib/libhairgen.so.$(VERSION)
EXLIB     := $(BUILD)/libexamples.a
PLATLIB   := $(BUILD)/libplatform.a
HAIRGEN   := $(BUILD)/hairgen
DENSE_SCENE := $(BUILD)/gen/dense.json
PROGRAMS  := $(patsubst examples/%.c,$(BUILD)/%,$(EXAMPLE_SRC))
TESTS     := $(patsubst tests/%.c,$(BUILD)/tests/%,$(TEST_SRC))
# Tests that render and so run a second time on softpipe (GALLIUM_DRIVER=
# softpipe), Mesa's second driver; every test runs on llvmpipe.
SOFTPIPE_TESTS := test_render_app_state test_render_drivers test_render_buffer_arrays test_render_marschner test_render_fixed test_render_fixed4 test_render_gl11 test_render_glsl_compile \
                  test_render_passes test_render_probe test_render_robustness test_render_scenes test_render_es3 test_render_es1
$(foreach t,$(filter-out $(notdir $(TESTS)),$(SOFTPIPE_TESTS)),$(error SOFTPIPE_TESTS: no tests/$(t).c))
# Render tests that run once more on llvmpipe through EGL (a pbuffer on
# Mesa's surfaceless platform) instead of OSMesa: HAIRTIER_CONTEXT=egl
# (tests/support_osmesa.h). A representative set: both GLSL tiers and the
# profiles (passes), the oracle probe, fixed4 and gl11.
EGL_TESTS := test_render_passes test_render_probe test_render_fixed4 test_render_gl11
$(foreach t,$(filter-out $(notdir $(TESTS)),$(EGL_TESTS)),$(error EGL_TESTS: no tests/$(t).c))
DEPS_STAMP := $(BUILD)/.deps-installed

.PHONY: all deps test test-runs accuracy asan bench demo clean fuzz fuzz-build fuzz-seeds fuzz-smoke check-valgrind install uninstall report-check
# Keep objects that pattern rules build on the way (tests, examples).
.SECONDARY:
.DEFAULT_GOAL := all

all: $(LIB) $(SHLIB) $(GENSHLIB) $(HAIRGEN) $(PROGRAMS) $(DENSE_SCENE)

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

$(BUILD)/obj/%.o: %.cpp | $(DEPS_STAMP)
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -std=c++17 -fno-rtti -Wall -Wextra $(WERROR) $(OPT) $(SAN) $(if $(SAN),-fno-sanitize=vptr) -MMD -MP -c $< -o $@

# The gl11 tier's per-vertex loops vectorise with sqrtf inline and selects
# if-converted (neither flag changes a result; fallback/gl11_program.c).
# The per-vertex loops of the tiers that do CPU work (structure of arrays)
# vectorise only without errno from sqrtf and at -O3's cost model; neither
# flag changes a result.
$(BUILD)/obj/fallback/gl11_program.o: CFLAGS += -fno-math-errno -fno-trapping-math
$(BUILD)/obj/fallback/fixed_soa.o $(BUILD)/obj/fallback/fixed4_program.o: CFLAGS += -O3 -fno-math-errno -fno-trapping-math
# The fixed tier's LUT bake, likewise (the same bytes, fewer instructions).
$(BUILD)/obj/shadergen/emit_fixed.o: CFLAGS += -O3 -fno-math-errno -fno-trapping-math
# The PNG rows' "up" filter: GCC vectorises it at -O3's cost model only.
$(BUILD)/obj/shadergen/png_encode.o: CFLAGS += -O3

# The libraries' objects serve the archives and the shared libraries alike:
# position-independent, and nothing visible beyond HT_API (export.h).
$(call obj,$(RUNTIME_SRC) $(GEN_SRC) $(PLATFORM_SRC)): CFLAGS += -fPIC -fvisibility=hidden
$(patsubst %.cpp,$(BUILD)/obj/%.o,$(GEN_CXX_SRC)): CXXFLAGS += -fPIC -fvisibility=hidden

# $(1): the library as libNAME.so (in $(BUILD)/lib), $(2): what it links;
# makes libNAME.so.$(VERSION) and the libNAME.so.$(SOVERSION) and libNAME.so links.
define shared_library
	@mkdir -p $(dir $(1))
	$(CC) $(LDFLAGS) -shared -Wl,-soname,$(notdir $(1)).$(SOVERSION) -Wl,-z,defs \
	  -Wl,--exclude-libs,ALL -o $(1).$(VERSION) $(2)
	ln -sf $(notdir $(1)).$(VERSION) $(1).$(SOVERSION)
	ln -sf $(notdir $(1)).$(SOVERSION) $(1)
endef

$(SHLIB): $(call obj,$(RUNTIME_SRC))
	$(call shared_library,$(BUILD)/lib/libhairtier.so,$^ $(CORE_LIBS))

# libhairgen.so carries the runtime pieces it uses privately (exclude-libs),
# and the offscreen context measure.c draws in; an application gets the
# runtime's API from libhairtier.so.
$(GENSHLIB): $(call obj,$(GEN_SRC)) $(patsubst %.cpp,$(BUILD)/obj/%.o,$(GEN_CXX_SRC)) $(PLATLIB) $(LIB)
	$(call shared_library,$(BUILD)/lib/libhairgen.so,$^ $(GLSLANG_LIBS) $(GEN_LIBS) $(CORE_LIBS))

$(LIB): $(call obj,$(RUNTIME_SRC))
	@rm -f $@
	ar rcs $@ $^

$(GENLIB): $(call obj,$(GEN_SRC)) $(patsubst %.cpp,$(BUILD)/obj/%.o,$(GEN_CXX_SRC))
	@rm -f $@
	ar rcs $@ $^

$(EXLIB): $(call obj,$(EXAMPLE_LIB_SRC))
	@rm -f $@
	ar rcs $@ $^

$(PLATLIB): $(call obj,$(PLATFORM_SRC))
	@rm -f $@
	ar rcs $@ $^

# The version every program's --version prints: VERSION, defined once below.
$(BUILD)/obj/platform/cli.o $(BUILD)/obj/tests/test_programs.o: CPPFLAGS += -DHT_VERSION='"$(VERSION)"'
$(BUILD)/obj/platform/cli.o $(BUILD)/obj/tests/test_programs.o: Makefile

# hairgen starts once per material in a build farm: no GL linked (--measure
# loads libOSMesa or libEGL with dlopen, platform/offscreen.c), libstdc++,
# libdeflate, libpng and zlib linked in, not position-independent, so a
# start relocates almost nothing.
$(HAIRGEN): $(call obj,shadergen/hairgen.c) $(GENLIB) $(PLATLIB) $(LIB)
	$(CC) $(LDFLAGS) -no-pie $^ $(filter-out -lstdc++,$(GLSLANG_LIBS)) \
	  -Wl,-Bstatic -lstdc++ $(GEN_LIBS) -lpng16 -lz -Wl,-Bdynamic -lcjson -lpthread -lm -o $@

# The dense groom (docs/lod.md): tools/densegroom writes 100 000 strands as
# a .hair file (19 MB, deterministic, not committed) and the "strands" scene
# that draws it, both in $(BUILD)/gen.
$(BUILD)/densegroom: tools/densegroom.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $< -lm -o $@
$(DENSE_SCENE): $(BUILD)/densegroom
	@mkdir -p $(dir $@)
	$(BUILD)/densegroom -o $(BUILD)/gen/dense.hair --scene $@

# hairview draws a bundle: the runtime only, no generator, no glslang.
$(BUILD)/hairview: $(BUILD)/obj/examples/hairview.o $(EXLIB) $(PLATLIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(CORE_LIBS) $(OFFSCREEN_LIBS) -o $@

# png_metrics compares two PNGs: the generator's metrics (libhairgen), no
# GL (it runs on a device machine beside hairview).
$(BUILD)/png_metrics: $(BUILD)/obj/examples/png_metrics.o $(GENLIB) $(PLATLIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(CORE_LIBS) -o $@

# The programs that draw get the context module from EXLIB: OSMesa by
# dlopen, EGL linked; libOSMesa stays off their NEEDED list (--as-needed,
# GCC's default here), so they start where there is no OSMesa.
$(BUILD)/%: $(BUILD)/obj/examples/%.o $(EXLIB) $(GENLIB) $(PLATLIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) $(OFFSCREEN_LIBS) -o $@

# The benchmarks' modules are tested like the library's (tests/test_bench_*.c);
# tests make their contexts with the programs' module (tests/support_osmesa.c).
$(BUILD)/obj/tests/%.o: CPPFLAGS += -Iexamples
# The tests' own code does little arithmetic (the library's is -O2): unoptimised, with
# line tables, it compiles in a third of -O2 -g's time and the runs take as long.
$(BUILD)/obj/tests/%.o: OPT = -O0 -g1
$(BUILD)/obj/tests/test_bench%.o: CPPFLAGS += -Iexamples/bench

# The tests' support modules are an archive too: a test links the ones it
# calls, and glslang only if it generates.
TESTLIB := $(BUILD)/libtestsupport.a
$(TESTLIB): $(call obj,$(TEST_SUPPORT_SRC))
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/tests/%: $(BUILD)/obj/tests/%.o $(TESTLIB) $(EXLIB) $(GENLIB) $(PLATLIB) $(LIB)
	@mkdir -p $(dir $@)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) $(OFFSCREEN_LIBS) -lcmocka -o $@

# The bundle as one C header (hairgen --emit-header) of the render tests'
# fixture (dark-brown x furball), compiled into test_render_bundle_memory and
# checked to build warning-free as C99 and as C++ (tests/data/header_use.c).
GEN_HEADER := $(BUILD)/gen/dark_brown_furball.h
$(GEN_HEADER): $(HAIRGEN) materials/dark-brown.json scenes/furball.json
	@mkdir -p $(dir $@)
	$(HAIRGEN) materials/dark-brown.json --scene scenes/furball.json --emit-header $@ \
	  --header-symbol dark_brown_furball >/dev/null
$(BUILD)/gen/header_use_c99.o: tests/data/header_use.c $(GEN_HEADER)
	$(CC) -std=c99 -Wall -Wextra -pedantic -Werror -Iinclude -I$(BUILD)/gen -c $< -o $@
$(BUILD)/gen/header_use_cxx.o: tests/data/header_use.c $(GEN_HEADER)
	$(CXX) -x c++ -Wall -Wextra -pedantic -Werror -Iinclude -I$(BUILD)/gen -c $< -o $@
$(BUILD)/obj/tests/test_render_bundle_memory.o: CPPFLAGS += -I$(BUILD)/gen
$(BUILD)/obj/tests/test_render_bundle_memory.o: $(GEN_HEADER) $(BUILD)/gen/header_use_c99.o \
                                                $(BUILD)/gen/header_use_cxx.o

# ---- make test: each run a target of its own, JOBS at a time ----
# Every test binary runs from the repository root, on llvmpipe through
# OSMesa; those in SOFTPIPE_TESTS run again on softpipe, those in EGL_TESTS
# again on llvmpipe through EGL; then the test scripts (make install into a
# temporary prefix and programs built against it). Each run's output goes to
# TEST_RESULTS/RUN.log (tests/run_test.sh); tests/test_summary.sh prints the
# failed runs' logs and "binaries: N passed, N failed".
JOBS         ?= $(shell nproc)
TEST_RESULTS := $(BUILD)/test-results
TEST_SCRIPTS := tests/install_test.sh tests/header_examples.sh
# Tests that run the programs (HAIRTIER_BUILD) wait for them.
PROGRAM_TESTS := $(notdir $(basename $(shell grep -l 'HAIRTIER_BUILD\|ht_test_build_dir' $(TEST_SRC))))
# The slowest runs first (most CPU first, docs/performance.md "Test suite
# time"), so the last ones to end are short.
SLOW_RUNS := test_render_accuracy.llvmpipe test_render_marschner.llvmpipe test_measure.llvmpipe \
             test_render_drivers.llvmpipe test_thin_strands.llvmpipe test_marschner_lut.llvmpipe \
             test_render_scenes.llvmpipe install_test.script test_render_faults.llvmpipe \
             test_hairgen_batch.llvmpipe test_marschner_fit.llvmpipe test_render_marschner.softpipe \
             test_emit_glsl.llvmpipe test_mediump.llvmpipe test_render_es1.llvmpipe test_measure_lod.llvmpipe \
             test_render_es3.llvmpipe test_render_fixed.softpipe test_model_marschner.llvmpipe \
             test_render_es2.llvmpipe test_render_passes.softpipe
ALL_RUNS  := $(notdir $(TESTS:%=%.llvmpipe)) $(SOFTPIPE_TESTS:%=%.softpipe) $(EGL_TESTS:%=%.egl) \
             $(notdir $(TEST_SCRIPTS:%.sh=%.script))
$(foreach r,$(filter-out $(ALL_RUNS),$(SLOW_RUNS)),$(error SLOW_RUNS: no run $(r)))
# Under a sanitizer (make asan) no softpipe runs: they run the library's code
# that the llvmpipe runs do, on another driver, and the sanitizers check our
# code, not Mesa's.
RUNS      := $(if $(SAN),$(filter-out %.softpipe,$(ALL_RUNS)),$(ALL_RUNS))
TEST_RUNS := $(addprefix $(TEST_RESULTS)/,$(filter $(RUNS),$(SLOW_RUNS)) $(filter-out $(SLOW_RUNS),$(RUNS)))
RUN_TEST = HAIRTIER_BUILD=$(BUILD) tests/run_test.sh

# Bundles several render tests share, MATERIAL/SCENE (tests/support_render.h,
# ht_test_bundle): a Marschner material's bake and fit cost about 2 s a
# bundle, the others about 0.15 s, built once here instead of once per test
# run (dark-brown x furball: the fur-ball fixture of fifteen tests, each on
# one to three drivers). No stored levels (--no-lods): no test drawing them
# needs them.
FIXTURE_BUNDLES := $(addprefix $(BUILD)/fixtures/brown-marschner/,backlit furball patches ratboy) \
  $(addprefix $(BUILD)/fixtures/dark-brown/,furball patches ratboy) \
  $(addprefix $(BUILD)/fixtures/blond/,furball patches) $(addprefix $(BUILD)/fixtures/kajiya-kay/,furball ratboy)
$(BUILD)/fixtures/%: $(HAIRGEN) $(wildcard materials/*.json scenes/*.json)
	@rm -rf $@ && mkdir -p $(dir $@)
	@$(HAIRGEN) -q materials/$(notdir $(patsubst %/,%,$(dir $*))).json --scene scenes/$(notdir $*).json --no-lods -o $@

$(foreach t,$(PROGRAM_TESTS),$(eval $(TEST_RESULTS)/$(t).llvmpipe $(TEST_RESULTS)/$(t).softpipe \
  $(TEST_RESULTS)/$(t).egl: $(HAIRGEN) $(PROGRAMS) $(BUILD)/densegroom))
$(TEST_RESULTS)/%.llvmpipe: $(BUILD)/tests/% | $(TEST_RESULTS)/.dir $(FIXTURE_BUNDLES)
	@$(RUN_TEST) $@ llvmpipe osmesa $<
# On softpipe only the cases whose outcome is the driver's (tests/support_driver.h).
$(TEST_RESULTS)/%.softpipe: $(BUILD)/tests/% | $(TEST_RESULTS)/.dir $(FIXTURE_BUNDLES)
	@HAIRTIER_DRIVER_CASES=1 $(RUN_TEST) $@ softpipe osmesa $<
$(TEST_RESULTS)/%.egl: $(BUILD)/tests/% | $(TEST_RESULTS)/.dir $(FIXTURE_BUNDLES)
	@$(RUN_TEST) $@ llvmpipe egl $<
$(TEST_RESULTS)/%.script: tests/%.sh all | $(TEST_RESULTS)/.dir
	@BUILD=$(BUILD) CC="$(CC)" SAN="$(SAN)" LD_GOLD="$(LD_GOLD)" $(RUN_TEST) $@ llvmpipe osmesa sh $<
$(TEST_RESULTS)/.dir:
	@mkdir -p $(dir $@) && touch $@

test-runs: $(TEST_RUNS) all
# -jJOBS for a sub-make, unless make was given -j.
PARALLEL = $(if $(filter -j%,$(MAKEFLAGS)),,-j$(JOBS))
test:
	@rm -rf $(TEST_RESULTS)
	@$(MAKE) --no-print-directory $(PARALLEL) test-runs
	@tests/test_summary.sh $(TEST_RESULTS)

# The accuracy sweep at each shipped scene's own size and hair count
# (docs/accuracy.md, "Every shipped pair at its shipped size"; about 25
# times the pinned 256² sweep that make test runs): its lines, then pass or fail.
ACCURACY_RESULTS := $(BUILD)/accuracy-results
accuracy: $(BUILD)/tests/test_render_accuracy
	@rm -rf $(ACCURACY_RESULTS) && mkdir -p $(ACCURACY_RESULTS)
	@HAIRTIER_SWEEP=shipped $(RUN_TEST) $(ACCURACY_RESULTS)/shipped-sweep llvmpipe osmesa $<
	@grep '^shipped' $(ACCURACY_RESULTS)/shipped-sweep.log || true
	@tests/test_summary.sh $(ACCURACY_RESULTS)

# -g1: line tables for the sanitizers' reports, without the full debug info that slows compiling and linking.
asan:
	LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 \
	$(MAKE) BUILD=build-asan OPT="-O1 -g1 -fno-omit-frame-pointer" \
	  SAN="-fsanitize=address,undefined -fno-sanitize-recover=undefined" test

# Every benchmark through build/bench_suite: the generator and mesh figures,
# the frame benchmark per scene on llvmpipe and on softpipe (an interpreter:
# a stand-in for a slow fragment unit, smaller so it ends), the fur-ball
# scaling series; then bench/results.csv, results.md, results.svg, scaling.svg.
bench: all
	@HAIRTIER_BUILD=$(BUILD) $(BUILD)/bench_suite -o bench

demo: all
	@mkdir -p out
	@for scene in furball patches ratboy; do \
	  echo "== $$scene: hairgen materials/dark-brown.json --scene scenes/$$scene.json -o out/$$scene-bundle"; \
	  $(HAIRGEN) materials/dark-brown.json --scene scenes/$$scene.json -o out/$$scene-bundle || exit 1; \
	  echo "== $$scene: hairview --bundle out/$$scene-bundle --scene scenes/$$scene.json -o out/$$scene.png"; \
	  $(BUILD)/hairview --bundle out/$$scene-bundle --scene scenes/$$scene.json -o out/$$scene.png || exit 1; \
	done
	@echo "== backlit: hairgen materials/brown-marschner.json --scene scenes/backlit.json -o out/backlit-bundle"
	@$(HAIRGEN) materials/brown-marschner.json --scene scenes/backlit.json -o out/backlit-bundle
	@echo "== backlit: hairview --bundle out/backlit-bundle --scene scenes/backlit.json -o out/backlit.png"
	@$(BUILD)/hairview --bundle out/backlit-bundle --scene scenes/backlit.json -o out/backlit.png
	@echo "== es2: hairview --bundle out/patches-bundle --scene scenes/patches.json --api gles2 -o out/patches-es2.png (GL ES 2.0 through EGL)"
	@EGL_PLATFORM=surfaceless MESA_GLES_VERSION_OVERRIDE=2.0 $(BUILD)/hairview --bundle out/patches-bundle \
	  --scene scenes/patches.json --api gles2 -o out/patches-es2.png
	@echo "demo: wrote out/furball.png, out/patches.png, out/ratboy.png, out/backlit.png (the marschner tier lit from behind) and out/patches-es2.png (the patches on GL ES 2.0); bundles in out/SCENE-bundle"

# ---- install: make install PREFIX=/usr/local DESTDIR= ; make uninstall ----
# The libraries (shared with their links, and static), the public headers
# (include/hairtier/, included as <hairtier/NAME.h>), the two programs, a
# pkg-config file per library and a CMake package (find_package(hairtier)).
# tests/install_test.sh installs into a temporary prefix and builds C and
# C++ programs against it with pkg-config and with CMake only.
PREFIX  ?= /usr/local
DESTDIR ?=
PUBLIC_HEADERS := $(wildcard include/hairtier/*.h)
INSTALL_BIN := $(DESTDIR)$(PREFIX)/bin
INSTALL_LIB := $(DESTDIR)$(PREFIX)/lib
INSTALL_INC := $(DESTDIR)$(PREFIX)/include/hairtier
INSTALL_PC  := $(INSTALL_LIB)/pkgconfig
INSTALL_CMAKE := $(INSTALL_LIB)/cmake/hairtier
PC_FILES    := runtime/hairtier.pc.in shadergen/hairgen.pc.in
CMAKE_FILES := runtime/hairtierConfig.cmake.in runtime/hairtierConfigVersion.cmake.in
SHARED_NAMES := $(foreach l,libhairtier libhairgen,$(l).so $(l).so.$(SOVERSION) $(l).so.$(VERSION))

install: $(LIB) $(GENLIB) $(SHLIB) $(GENSHLIB) $(HAIRGEN) $(BUILD)/hairview
	install -d $(INSTALL_BIN) $(INSTALL_LIB) $(INSTALL_INC) $(INSTALL_PC) $(INSTALL_CMAKE)
	install -m 755 $(HAIRGEN) $(BUILD)/hairview $(INSTALL_BIN)/
	install -m 644 $(LIB) $(GENLIB) $(INSTALL_LIB)/
	install -m 755 $(SHLIB) $(GENSHLIB) $(INSTALL_LIB)/
	cp -P $(BUILD)/lib/libhairtier.so $(BUILD)/lib/libhairtier.so.$(SOVERSION) \
	  $(BUILD)/lib/libhairgen.so $(BUILD)/lib/libhairgen.so.$(SOVERSION) $(INSTALL_LIB)/
	install -m 644 $(PUBLIC_HEADERS) $(INSTALL_INC)/
	@glslang=$$(pkg-config --libs-only-l glslang | sed -e 's/-l//g' -e 's/ *$$//' -e 's/  */;/g'); \
	for f in $(PC_FILES) $(CMAKE_FILES); do \
	  case $$f in *.pc.in) dir=$(INSTALL_PC);; *) dir=$(INSTALL_CMAKE);; esac; \
	  out=$$dir/$$(basename $$f .in); echo "write $$out"; \
	  sed -e 's|@PREFIX@|$(PREFIX)|g' -e 's|@VERSION@|$(VERSION)|g' -e 's|@SOVERSION@|$(SOVERSION)|g' \
	      -e "s|@GLSLANG_LIBS@|$$glslang;glslang-default-resource-limits|g" $$f > $$out.tmp && mv $$out.tmp $$out || exit 1; \
	done

uninstall:
	rm -f $(INSTALL_BIN)/hairgen $(INSTALL_BIN)/hairview
	rm -f $(INSTALL_LIB)/$(notdir $(LIB)) $(INSTALL_LIB)/$(notdir $(GENLIB)) $(addprefix $(INSTALL_LIB)/,$(SHARED_NAMES))
	rm -f $(addprefix $(INSTALL_INC)/,$(notdir $(PUBLIC_HEADERS)))
	rm -f $(addprefix $(INSTALL_PC)/,$(basename $(notdir $(PC_FILES))))
	rm -f $(addprefix $(INSTALL_CMAKE)/,$(basename $(notdir $(CMAKE_FILES))))
	@rmdir $(INSTALL_INC) $(INSTALL_CMAKE) 2>/dev/null || true

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
	$(MAKE) $(PARALLEL) BUILD=$(FUZZ_BUILD) CC=clang CXX=clang++ OPT="-O1 -g1 -fno-omit-frame-pointer" SAN="$(FUZZ_SAN)" \
	  $(patsubst %,$(FUZZ_BUILD)/fuzz/%,$(FUZZ_TARGETS))

# Seeds: the shipped materials and scenes, a generated bundle's manifest,
# combiner program and PNGs, the small strand files of tests/data/strands; each target's corpus grows in $(FUZZ_BUILD)/corpus.
fuzz-seeds: $(HAIRGEN)
	@rm -rf $(FUZZ_BUILD)/seeds && mkdir -p $(FUZZ_BUILD)/seeds/fuzz_material $(FUZZ_BUILD)/seeds/fuzz_scene \
	  $(FUZZ_BUILD)/seeds/fuzz_manifest $(FUZZ_BUILD)/seeds/fuzz_combiner $(FUZZ_BUILD)/seeds/fuzz_png \
	  $(FUZZ_BUILD)/seeds/fuzz_json $(FUZZ_BUILD)/seeds/fuzz_fixed4 $(FUZZ_BUILD)/seeds/fuzz_gl11 \
	  $(FUZZ_BUILD)/seeds/fuzz_strands_tfx $(FUZZ_BUILD)/seeds/fuzz_strands_hair
	@$(HAIRGEN) materials/dark-brown.json --scene scenes/furball.json --no-lods -o $(FUZZ_BUILD)/seed-bundle >/dev/null
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
	@cp tests/data/strands/*.tfx $(FUZZ_BUILD)/seeds/fuzz_strands_tfx/
	@cp tests/data/strands/*.hair $(FUZZ_BUILD)/seeds/fuzz_strands_hair/
	@rm -rf $(FUZZ_BUILD)/seed-cards && mkdir -p $(FUZZ_BUILD)/seeds/fuzz_lod_file
	@$(HAIRGEN) --cards $(FUZZ_BUILD)/seed-bundle --scene scenes/patches.json --strands-per-card 8 \
	  -o $(FUZZ_BUILD)/seed-cards >/dev/null
	@cp $(FUZZ_BUILD)/seed-cards/lods.bin $(FUZZ_BUILD)/seeds/fuzz_lod_file/a.bin
	@$(HAIRGEN) materials/dark-brown.json --scene scenes/patches.json -o $(FUZZ_BUILD)/seed-bundle-patches >/dev/null
	@cp $(FUZZ_BUILD)/seed-bundle-patches/lods.bin $(FUZZ_BUILD)/seeds/fuzz_lod_file/b.bin

# Each target for FUZZ_SECONDS; its last lines (runs, coverage, any crash)
# go to $(FUZZ_BUILD)/TARGET.log, a summary line per target to stdout.
# Each target a job of its own, JOBS at a time (-k: every target runs even if one fails).
FUZZ_RUNS := $(FUZZ_TARGETS:%=$(FUZZ_BUILD)/runs/%)
fuzz: fuzz-build fuzz-seeds
	@rm -rf $(FUZZ_BUILD)/runs; status=0; $(MAKE) --no-print-directory -k $(PARALLEL) $(FUZZ_RUNS) || status=1; \
	  rm -f /tmp/hairtier-fuzz-png-*.png; exit $$status
$(FUZZ_BUILD)/runs/%:
	@mkdir -p $(dir $@) $(FUZZ_BUILD)/corpus/$* $(FUZZ_BUILD)/crashes/$*
	@if $(FUZZ_BUILD)/fuzz/$* -max_total_time=$(FUZZ_SECONDS) -rss_limit_mb=2048 -timeout=10 -max_len=65536 \
	     -print_final_stats=1 -artifact_prefix=$(FUZZ_BUILD)/crashes/$*/ \
	     $(FUZZ_BUILD)/corpus/$* $(FUZZ_BUILD)/seeds/$* > $(FUZZ_BUILD)/$*.log 2>&1; then r=ok; \
	else r=FAILED; fi; \
	echo "$*: $$r, $$(grep -o 'stat::number_of_executed_units: *[0-9]*' $(FUZZ_BUILD)/$*.log | grep -o '[0-9]*$$') runs in $(FUZZ_SECONDS) s, corpus $$(ls $(FUZZ_BUILD)/corpus/$* | wc -l), $$(grep -o 'cov: [0-9]*' $(FUZZ_BUILD)/$*.log | tail -1)"; \
	[ $$r = ok ] && touch $@

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

# ---- haircompare's report in a real browser ----
# Debian's chromium is installed here only (it is big, and nothing else
# needs it). The report of the fur ball's five 512² tiers (and, its bundle
# measured with --measure-lods, its level x tier grid) must fit a
# REPORT_WIDTH px window: laid out by Chromium at that width, its
# scrollWidth is at most REPORT_WIDTH. Then every <img> of it must be found,
# full size, in a screenshot of the whole page at that width
# (tests/report_screenshot_check.c). Then each check must fail on a page
# made to fail it (one image deleted; a block 2000 px wide), so both can.
# The bundle's soft cells at two factors, 2 and 3: a grid row each at the
# cheapest (hairgen's default 3, 6 and 8 take its cells from 82 to 204 s).
REPORT_CHECK := out/report-check
REPORT_WIDTH := 1400
CHROMIUM := chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
            --disable-background-networking --disable-component-update --disable-sync \
            --force-device-scale-factor=1 --force-color-profile=srgb --hide-scrollbars
# $(1): page, $(2): screenshot, $(3): its height; Chromium's chatter goes to a log shown on failure.
define screenshot
	@profile=$$(mktemp -d) && $(CHROMIUM) --window-size=$(REPORT_WIDTH),$(3) --user-data-dir=$$profile \
	  --screenshot=$(CURDIR)/$(2) file://$(CURDIR)/$(1) >$(REPORT_CHECK)/chromium.log 2>&1; rc=$$?; rm -rf $$profile; \
	[ $$rc -eq 0 ] && [ -s $(2) ] || { cat $(REPORT_CHECK)/chromium.log; echo "report-check: chromium failed"; exit 1; }
endef
# "WIDTH HEIGHT" of page $(1) laid out at REPORT_WIDTH into file $(2): a copy
# beside it (the report runs no script) gets one that writes the root's
# scroll size into the DOM after load, which --dump-dom prints.
define page_size
	@sed 's|</body>|<script>addEventListener("load",function(){var e=document.documentElement;document.body.setAttribute("data-page-size",e.scrollWidth+" "+e.scrollHeight)})</script></body>|' \
	  $(1) >$(1).size.html && profile=$$(mktemp -d) && \
	$(CHROMIUM) --window-size=$(REPORT_WIDTH),1000 --user-data-dir=$$profile --dump-dom file://$(CURDIR)/$(1).size.html \
	  2>$(REPORT_CHECK)/chromium.log | sed -n 's/.*data-page-size="\([0-9]*\) \([0-9]*\)".*/\1 \2/p' >$(2); \
	rm -rf $$profile $(1).size.html; \
	[ -s $(2) ] || { cat $(REPORT_CHECK)/chromium.log; echo "report-check: chromium did not lay out $(1)"; exit 1; }
endef

report-check: all $(BUILD)/tests/report_screenshot_check
	$(call install_missing,chromium)
	@rm -rf $(REPORT_CHECK) && mkdir -p $(REPORT_CHECK)
	$(HAIRGEN) materials/dark-brown.json --scene scenes/furball.json --measure-lods --lod-soften 2,3 -o $(REPORT_CHECK)/bundle >/dev/null
	$(BUILD)/haircompare --bundle $(REPORT_CHECK)/bundle --scene scenes/furball.json --frames 3 -o $(REPORT_CHECK)/report
	$(call page_size,$(REPORT_CHECK)/report/index.html,$(REPORT_CHECK)/size)
	@read w h <$(REPORT_CHECK)/size; echo "report-check: the page is $$w x $$h px in a $(REPORT_WIDTH) px window"; \
	[ $$w -le $(REPORT_WIDTH) ] || { echo "report-check: the page is $$w px wide: it needs a sideways scroll"; exit 1; }
	$(call screenshot,$(REPORT_CHECK)/report/index.html,$(REPORT_CHECK)/screenshot.png,$$(cut -d' ' -f2 $(REPORT_CHECK)/size))
	$(BUILD)/tests/report_screenshot_check $(REPORT_CHECK)/screenshot.png $(REPORT_CHECK)/report
	@cp -r $(REPORT_CHECK)/report $(REPORT_CHECK)/broken && rm $(REPORT_CHECK)/broken/vertex-error.png
	$(call screenshot,$(REPORT_CHECK)/broken/index.html,$(REPORT_CHECK)/broken.png,$$(cut -d' ' -f2 $(REPORT_CHECK)/size))
	@if $(BUILD)/tests/report_screenshot_check $(REPORT_CHECK)/broken.png $(REPORT_CHECK)/report >/dev/null 2>&1; then \
	  echo "report-check: the checker found an image the page could not load"; exit 1; fi
	@sed 's|</body>|<div style="width:2000px">wide</div></body>|' $(REPORT_CHECK)/report/index.html >$(REPORT_CHECK)/broken/wide.html
	$(call page_size,$(REPORT_CHECK)/broken/wide.html,$(REPORT_CHECK)/wide-size)
	@read w h <$(REPORT_CHECK)/wide-size; if [ $$w -le $(REPORT_WIDTH) ]; then \
	  echo "report-check: the width check missed a 2000 px block ($$w px)"; exit 1; fi
	@echo "report-check: $(REPORT_CHECK)/report/index.html fits a $(REPORT_WIDTH) px window and every image of it" \
	  "loaded in Chromium (screenshot $(REPORT_CHECK)/screenshot.png); a missing image and a wide page are caught"

clean:
	rm -rf build build-asan build-fuzz out

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
