# strata — build, test, bench, demo. `make demo` and `make test` are the two
# set-up commands of the README; both start with `deps`, which installs the
# Debian packages only when one is missing.

DEB_PACKAGES := pocl-opencl-icd ocl-icd-opencl-dev opencl-headers clinfo \
                libopenexr-dev libtinygltf-dev nlohmann-json3-dev libstb-dev \
                libcairo2-dev libfftw3-dev libcmocka-dev libcjson-dev libpng-dev zlib1g-dev python3-venv \
                clang libclang-rt-14-dev oclgrind parallel pkg-config gcc g++ make help2man \
                python3-scipy libembree-dev slurm-wlm munge

# OpenEXR's tools: exrheader reads the AOV channels' names and types back
# (tests/cli/test_aov_cli.sh)
DEB_PACKAGES += openexr

PKGS     := OpenCL stb cairo fftw3

# The version `strata --version` prints and writes into its files: the
# release in the file VERSION, with git describe's distance from the commit
# that set it (0.1.0-N-gHASH, -dirty; tools/version.sh).
VERSION  := $(shell sh tools/version.sh)
PREFIX   ?= /usr/local
CC       ?= cc
CXX      ?= c++
OPT      ?= -O2
WARN     := -Wall -Wextra
# The modules, lowest first (docs/DESIGN.md; tests/unit/test_layers.sh checks
# that each includes only the ones below it), and the kernels' folders, which
# are also the kernels' include search path (tools/embed.c, STRATA_KERNEL_DIR).
MODULES     := base image device sampling filter bvh scene render lab cli
KERNEL_DIRS := shared sample geom integrator film
CPPFLAGS += -Iinclude $(MODULES:%=-Isrc/%) $(KERNEL_DIRS:%=-Ikernels/%) -I/usr/include/OpenEXR
CFLAGS   += -std=c11 -D_POSIX_C_SOURCE=200809L $(OPT) -g $(WARN)
CXXFLAGS += -std=c++17 $(OPT) -g $(WARN) -I/usr/include/stb -I/usr/include/nlohmann
LDLIBS   += -ltinygltf -lOpenEXRCore-3_1 -lcairo -lpng -lcjson -lz -lfftw3 -lstb -lOpenCL -lstdc++ -lm -lpthread

ifeq ($(SANITIZE),1)
  CFLAGS   += -fsanitize=address,undefined -fno-omit-frame-pointer
  CXXFLAGS += -fsanitize=address,undefined -fno-omit-frame-pointer
  LDFLAGS  += -fsanitize=address,undefined
  BUILD    := build/asan
else
  BUILD    := build/release
endif

# libFuzzer harnesses (tests/fuzz/): the library again, built by clang with
# ASan and UBSan and libFuzzer's coverage, in a folder of its own.
ifeq ($(FUZZ),1)
  CC       := clang
  CXX      := clang++
  FUZZ_SAN := -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
  CFLAGS   += -fsanitize=fuzzer-no-link $(FUZZ_SAN)
  CXXFLAGS += -fsanitize=fuzzer-no-link $(FUZZ_SAN)
  BUILD    := build/fuzz
endif

LIB_C    := $(filter-out src/cli/main.c,$(wildcard src/*/*.c))
LIB_CXX  := $(wildcard src/*/*.cpp)
LIB_OBJ  := $(LIB_C:src/%.c=$(BUILD)/obj/%.o) $(LIB_CXX:src/%.cpp=$(BUILD)/obj/%.o) \
            $(BUILD)/embedded.o $(BUILD)/version.o
HEADERS  := $(wildcard include/*.h) $(wildcard src/*/*.h) $(wildcard kernels/*/*.h)
# The kernel sources in the order of their file names, whatever their folder
# (the order they were always compiled in, one program).
KERNEL_CL := $(foreach n,$(sort $(notdir $(wildcard kernels/*/*.cl))),$(wildcard kernels/*/$(n)))
KERNELS  := $(wildcard kernels/*/*.cl) $(wildcard kernels/*/*.h)
SCENES   := $(wildcard scenes/*.gltf)
# Test programs are built into $(BUILD)/tests/ whatever their layer's folder.
TESTS_C  := $(wildcard tests/unit/test_*.c tests/device/test_*.c tests/image/test_*.c)
TEST_BIN := $(patsubst %.c,$(BUILD)/tests/%,$(notdir $(TESTS_C)))

.PHONY: all deps bench-deps test test-unit test-device test-image test-cli test-farm test-sanitize fuzz test-fuzz test-oclgrind bench demo pictures sheen-table clean install FORCE
all: strata

# Installs what is missing (a no-op on a ready machine).
deps:
	@missing=""; for p in $(DEB_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "deps: installing$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi
	@$(MAKE) --no-print-directory $(PYEXR) $(PYOIDN)

# OpenEXR's Python binding (pip's OpenEXR: Debian 12 packages none), in a venv
# of its own, for the test that reads strata's EXRs with another library
# (tests/cli/test_exr_python.sh). Without a network it is left out with a note,
# and that test skips saying so. Open Image Denoise's Python package (oidn,
# which bundles the library) joins it for the denoising check of
# tests/cli/test_aov_cli.sh (the stamp marks it installed), skipped with a note
# where pip cannot install it.
PYEXR := build/pyexr/bin/python
PYOIDN := build/pyexr/oidn.stamp
$(PYEXR):
	@python3 -m venv build/pyexr && build/pyexr/bin/pip install -q OpenEXR numpy \
	  || { rm -rf build/pyexr; echo "deps: OpenEXR's Python binding unavailable (pip failed); tests/cli/test_exr_python.sh will skip"; }
$(PYOIDN): | $(PYEXR)
	@[ -x $(PYEXR) ] && build/pyexr/bin/pip install -q oidn && touch $@ \
	  || echo "deps: Open Image Denoise's Python package (oidn) unavailable (pip failed); tests/cli/test_aov_cli.sh skips its denoising check"

strata: $(BUILD)/strata
	cp $< $@

$(BUILD)/strata: $(BUILD)/obj/cli/main.o $(BUILD)/libstrata.a
	$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/libstrata.a: $(LIB_OBJ)
	rm -f $@ && ar rcs $@ $^

$(BUILD)/obj/%.o: src/%.c $(HEADERS)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@ $<

$(BUILD)/obj/%.o: src/%.cpp $(HEADERS)
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -c -o $@ $<

# Kernels and built-in scenes are compiled into the binary (tools/embed.c).
$(BUILD)/embed: tools/embed.c | $(BUILD)
	$(CC) -std=c11 -O1 $(WARN) -o $@ $<

$(BUILD)/embedded.c: $(BUILD)/embed $(KERNELS) $(SCENES)
	$(BUILD)/embed $@ kernels $(KERNEL_DIRS:%=-I %) $(KERNEL_CL:kernels/%=%) -- $(SCENES)

$(BUILD)/embedded.o: $(BUILD)/embedded.c
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@ $<

# version.c is rewritten only when the version changed, so a build of the same
# commit relinks nothing.
$(BUILD)/version.c: FORCE | $(BUILD)
	@printf '#include "st_version.h"\nconst char st_version[] = "%s";\n' '$(VERSION)' > $@.tmp
	@if cmp -s $@.tmp $@; then rm -f $@.tmp; else mv $@.tmp $@; fi

$(BUILD)/version.o: $(BUILD)/version.c
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@ $<

# One rule per layer's folder: make takes the one whose source exists.
define TEST_RULE
$$(BUILD)/tests/%: tests/$(1)/%.c tests/device_fixture.h tests/scratch.h tests/skip.h $$(BUILD)/libstrata.a
	@mkdir -p $$(@D)
	$$(CC) $$(CPPFLAGS) -Itests $$(CFLAGS) -o $$@ $$< $$(BUILD)/libstrata.a -lcmocka $$(LDFLAGS) $$(LDLIBS)
endef
$(foreach l,unit device image,$(eval $(call TEST_RULE,$(l))))

$(BUILD):
	mkdir -p $(BUILD)

# The tests in five layers (docs/TESTING.md), a folder each under tests/.
# unit: host code alone, no OpenCL device, seconds (with the check of the
# modules' layering); device: the kernels through the library; image: whole
# renders against committed or independently rendered images; cli: the
# command-line scripts; farm: split renders through a private Slurm cluster
# (slurm-wlm, from deps). `make test` runs every layer, prints each one's
# time and ends with one line "N passed, N failed, N skipped" over all of
# them, after the reason of each skip.
layer_bins    = $(patsubst %.c,$(BUILD)/tests/%,$(notdir $(wildcard tests/$(1)/test_*.c)))
TEST_UNIT    := $(call layer_bins,unit)
UNIT_SH      := $(wildcard tests/unit/test_*.sh)
TEST_DEVICE  := $(call layer_bins,device)
TEST_IMAGE   := $(call layer_bins,image)
IMAGE_SH     := $(wildcard tests/image/test_*.sh)
TEST_CLI_SH  := $(wildcard tests/cli/test_*.sh)
TEST_FARM_SH := $(wildcard tests/farm/test_*.sh)
RUN_TESTS    := BUILD=$(BUILD) sh tests/run.sh

# The bench's Cornell box, made here (tools/make_cornell_box.py --bench):
# the comparison workload of `make bench` and tools/bench_peers.sh, and a
# scene of the device tests.
BENCH_SCENE := build/scenes/cornell-bench.gltf
$(BENCH_SCENE): tools/make_cornell_box.py
	@mkdir -p $(@D)
	python3 tools/make_cornell_box.py --bench $@

test: deps strata $(TEST_BIN) $(BUILD)/make_icosphere $(BUILD)/make_envmap $(BENCH_SCENE)
	@$(RUN_TESTS) --layer unit $(TEST_UNIT) $(UNIT_SH) --layer device $(TEST_DEVICE) \
	    --layer image $(TEST_IMAGE) $(IMAGE_SH) --layer cli $(TEST_CLI_SH) \
	    --layer farm $(TEST_FARM_SH)

test-unit: $(TEST_UNIT)
	@$(RUN_TESTS) --layer unit $(TEST_UNIT) $(UNIT_SH)

test-device: deps $(TEST_DEVICE) $(BENCH_SCENE)
	@$(RUN_TESTS) --layer device $(TEST_DEVICE)

test-image: deps strata $(TEST_IMAGE)
	@$(RUN_TESTS) --layer image $(TEST_IMAGE) $(IMAGE_SH)

test-cli: deps strata $(BUILD)/make_icosphere $(BUILD)/make_envmap
	@$(RUN_TESTS) --layer cli $(TEST_CLI_SH)

test-farm: deps strata
	@$(RUN_TESTS) --layer farm $(TEST_FARM_SH)

# The scene import and the malformed-file suite under AddressSanitizer and
# UndefinedBehaviorSanitizer (leak reports off: PoCL and fontconfig keep
# caches for the life of the process). CI runs it after `make test`.
test-sanitize: deps
	$(MAKE) SANITIZE=1 build/asan/strata build/asan/tests/test_scene
	@ASAN_OPTIONS=detect_leaks=0 STRATA=build/asan/strata \
	    sh tests/run.sh build/asan/tests/test_scene tests/cli/test_khronos.sh

# `make fuzz` builds the harnesses; `make test-fuzz` runs each for
# FUZZ_SECONDS, seeded from the project's scenes and EXRs (tests/fuzz/run.sh).
# CI runs it.
FUZZERS      := gltf exr
FUZZ_SECONDS ?= 60
fuzz: deps
	$(MAKE) FUZZ=1 $(FUZZERS:%=build/fuzz/fuzz_%)

build/fuzz/fuzz_%: tests/fuzz/fuzz_%.c $(BUILD)/libstrata.a
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@.o $<
	$(CXX) -fsanitize=fuzzer $(FUZZ_SAN) -o $@ $@.o $(BUILD)/libstrata.a $(LDLIBS)

test-fuzz: fuzz strata
	@sh tests/fuzz/run.sh $(FUZZ_SECONDS) $(FUZZERS)

# Tiny renders under oclgrind's API, race and uninitialised-memory checks
# (tests/oclgrind/run.sh). CI runs it.
test-oclgrind: deps strata
	@sh tests/oclgrind/run.sh

# The default scene with the default settings, then the comparison
# workload: the bench Cornell box, independent samples, box filter, paths of
# max depth 4 and direct lighting; then the trace benchmark (camera and
# random rays) on a 327,680-triangle icosphere and the bench Cornell box.
BENCH_OPTS  := --width 512 --height 512 --spp 64 --sampler random --filter box
ICOSPHERE   := $(BUILD)/bench/icosphere.gltf
bench: deps strata $(ICOSPHERE) $(BENCH_SCENE)
	./strata bench --width 512 --height 512 --spp 64 --integrator path
	./strata bench --width 512 --height 512 --spp 64 --integrator direct
	./strata bench $(BENCH_SCENE) $(BENCH_OPTS) --integrator path --max-depth 4
	./strata bench $(BENCH_SCENE) $(BENCH_OPTS) --integrator direct
	@for s in $(ICOSPHERE) $(BENCH_SCENE); do for k in camera random; do \
	  echo "./strata bench $$s --rays $$k"; ./strata bench $$s --rays $$k || exit 1; done; done

# The peers of tools/bench_peers.sh: tools/bench_embree.c, which this
# builds against Debian's Embree 3 (libembree-dev, in deps because
# tests/cli/test_bench_embree.sh checks that peer's rays against strata's);
# Mitsuba 3 from PyPI in a venv of its own, and Debian's libllvm19 for
# Mitsuba's LLVM variant (bench_mitsuba.py points DRJIT_LIBLLVM_PATH at it),
# only for benchmarks.
BENCH_DEB := libllvm19
BENCH_PY  := build/bench-py/bin/python
bench-deps: deps
	@missing=""; for p in $(BENCH_DEB); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "bench-deps: installing$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi
	@[ -x $(BENCH_PY) ] || python3 -m venv build/bench-py
	$(BENCH_PY) -m pip install -q mitsuba numpy
	@$(MAKE) --no-print-directory $(BUILD)/bench_embree

# The native Embree peer of the trace benchmark (tools/bench_embree.c, run
# by tools/bench_peers.sh): strata's scene loader and ray generator linked
# with Debian's Embree 3 (libembree-dev, from `make bench-deps`); only for
# benchmarks, so neither `make` nor `make test` builds it.
$(BUILD)/bench_embree: tools/bench_embree.c $(BUILD)/libstrata.a | $(BUILD)
	$(CC) $(CPPFLAGS) $(CFLAGS) -o $@ $< $(BUILD)/libstrata.a $(LDFLAGS) $(LDLIBS) -lembree3

# The trace benchmark's large mesh: a 327,680-triangle icosphere (level 7).
$(BUILD)/make_icosphere: tools/make_icosphere.c | $(BUILD)
	$(CC) -std=c11 -O2 $(WARN) -o $@ $< -lm
$(ICOSPHERE): $(BUILD)/make_icosphere
	@mkdir -p $(BUILD)/bench
	$(BUILD)/make_icosphere $(BUILD)/bench/icosphere 7

# The sheen's albedo table (tools/make_sheen_table.c), kept in the tree: it
# takes some seconds, and changes only with the sheen's definition.
$(BUILD)/make_sheen_table: tools/make_sheen_table.c | $(BUILD)
	$(CC) -std=c11 -O2 $(WARN) -o $@ $< -lm
sheen-table: $(BUILD)/make_sheen_table
	$(BUILD)/make_sheen_table > kernels/integrator/sheen_table.h

# Environment maps (tools/make_envmap.c): the sky of the README's model
# pictures and the compass that shows the map's orientation. The sky also
# ships, as scenes/envmaps/sky.hdr (11 kB; test_envmap.sh checks that it is
# this tool's).
ENVMAPS := build/envmaps/compass.hdr
$(BUILD)/make_envmap: tools/make_envmap.c | $(BUILD)
	$(CC) -std=c11 -O2 $(WARN) -o $@ $< -lstb -lm
build/envmaps/%.hdr: $(BUILD)/make_envmap
	@mkdir -p build/envmaps
	$(BUILD)/make_envmap $* $@

# The README's pictures, each made by its one line in tools/make_pictures.sh
# (tests/image/test_pictures.sh checks that a few of them are up to date).
pictures: deps strata $(ENVMAPS)
	sh tools/make_pictures.sh
	@echo "pictures: the README's discrepancy table (paste it in where it differs):"
	@sh tools/discrepancy_table.sh

demo: deps strata
	./strata render -o strata.exr -o strata.png

# The binary, a man page made by help2man from the --help texts, and the bash
# completion; DESTDIR for staged installs (packages).
install: strata $(BUILD)/strata.1
	install -D -m 755 strata $(DESTDIR)$(PREFIX)/bin/strata
	install -D -m 644 $(BUILD)/strata.1 $(DESTDIR)$(PREFIX)/share/man/man1/strata.1
	install -D -m 644 tools/strata.bash-completion \
	    $(DESTDIR)$(PREFIX)/share/bash-completion/completions/strata

COMMANDS := render bench pattern filter signal merge converge compare diff devices
$(BUILD)/strata.1: $(BUILD)/strata tools/strata.h2m tools/man-commands.sh
	sh tools/man-commands.sh $(BUILD)/strata $(COMMANDS) > $(BUILD)/strata.h2m
	help2man --no-info --include=$(BUILD)/strata.h2m --output=$@ $(BUILD)/strata

clean:
	rm -rf build strata
