# strata — build, test, bench, demo. `make demo` and `make test` are the two
# set-up commands of the README; both start with `deps`, which installs the
# Debian packages only when one is missing.

DEB_PACKAGES := pocl-opencl-icd ocl-icd-opencl-dev opencl-headers clinfo \
                libopenexr-dev libtinygltf-dev nlohmann-json3-dev libstb-dev \
                libcairo2-dev libfftw3-dev libcmocka-dev libcjson-dev libpng-dev parallel pkg-config gcc g++ make \
                help2man

PKGS     := OpenCL stb cairo fftw3

# The version `strata --version` prints and writes into its files: `git
# describe` of the checkout, or the fallback outside a git checkout (a tarball).
VERSION_FALLBACK := 0.1.0
VERSION  := $(shell git describe --tags --always --dirty 2>/dev/null || echo $(VERSION_FALLBACK))
PREFIX   ?= /usr/local
CC       ?= cc
CXX      ?= c++
OPT      ?= -O2
WARN     := -Wall -Wextra
CPPFLAGS += -Iinclude -Isrc -Ikernels -I/usr/include/OpenEXR
CFLAGS   += -std=c11 -D_POSIX_C_SOURCE=200809L $(OPT) -g $(WARN)
CXXFLAGS += -std=c++17 $(OPT) -g $(WARN) -I/usr/include/stb -I/usr/include/nlohmann
LDLIBS   += -ltinygltf -lOpenEXRCore-3_1 -lcairo -lpng -lcjson -lfftw3 -lstb -lOpenCL -lstdc++ -lm -lpthread

ifeq ($(SANITIZE),1)
  CFLAGS   += -fsanitize=address,undefined -fno-omit-frame-pointer
  CXXFLAGS += -fsanitize=address,undefined -fno-omit-frame-pointer
  LDFLAGS  += -fsanitize=address,undefined
  BUILD    := build/asan
else
  BUILD    := build/release
endif

LIB_C    := $(filter-out src/main.c,$(wildcard src/*.c))
LIB_CXX  := $(wildcard src/*.cpp)
LIB_OBJ  := $(LIB_C:src/%.c=$(BUILD)/%.o) $(LIB_CXX:src/%.cpp=$(BUILD)/%.o) \
            $(BUILD)/embedded.o $(BUILD)/version.o
KERNELS  := $(wildcard kernels/*.cl) $(wildcard kernels/*.h)
SCENES   := $(wildcard scenes/*.gltf)
TESTS_C  := $(wildcard tests/test_*.c)
TEST_BIN := $(TESTS_C:tests/%.c=$(BUILD)/tests/%)

.PHONY: all deps test test-sanitize bench demo pictures clean install FORCE
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

strata: $(BUILD)/strata
	cp $< $@

$(BUILD)/strata: $(BUILD)/main.o $(BUILD)/libstrata.a
	$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/libstrata.a: $(LIB_OBJ)
	rm -f $@ && ar rcs $@ $^

$(BUILD)/%.o: src/%.c $(wildcard include/*.h) $(wildcard src/*.h) $(wildcard kernels/*.h) | $(BUILD)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@ $<

$(BUILD)/%.o: src/%.cpp $(wildcard include/*.h) $(wildcard src/*.h) | $(BUILD)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -c -o $@ $<

# Kernels and built-in scenes are compiled into the binary (tools/embed.c).
$(BUILD)/embed: tools/embed.c | $(BUILD)
	$(CC) -std=c11 -O1 $(WARN) -o $@ $<

$(BUILD)/embedded.c: $(BUILD)/embed $(KERNELS) $(SCENES)
	$(BUILD)/embed $@ $(wildcard kernels/*.cl) -- $(SCENES)

$(BUILD)/embedded.o: $(BUILD)/embedded.c
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@ $<

# version.c is rewritten only when the version changed, so a build of the same
# commit relinks nothing.
$(BUILD)/version.c: FORCE | $(BUILD)
	@printf '#include "st_version.h"\nconst char st_version[] = "%s";\n' '$(VERSION)' > $@.tmp
	@if cmp -s $@.tmp $@; then rm -f $@.tmp; else mv $@.tmp $@; fi

$(BUILD)/version.o: $(BUILD)/version.c
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@ $<

$(BUILD)/tests/%: tests/%.c $(BUILD)/libstrata.a | $(BUILD)
	@mkdir -p $(BUILD)/tests
	$(CC) $(CPPFLAGS) $(CFLAGS) -o $@ $< $(BUILD)/libstrata.a -lcmocka $(LDFLAGS) $(LDLIBS)

$(BUILD):
	mkdir -p $(BUILD)

test: deps strata $(TEST_BIN)
	@BUILD=$(BUILD) sh tests/run.sh $(TEST_BIN) $(wildcard tests/test_*.sh)

# The scene import and the malformed-file suite under AddressSanitizer and
# UndefinedBehaviorSanitizer (leak reports off: PoCL and fontconfig keep
# caches for the life of the process). CI runs it after `make test`.
test-sanitize: deps
	$(MAKE) SANITIZE=1 build/asan/strata build/asan/tests/test_scene
	@ASAN_OPTIONS=detect_leaks=0 STRATA=build/asan/strata \
	    sh tests/run.sh build/asan/tests/test_scene tests/test_khronos.sh

# The default scene with the default settings, then (where ../shared is
# present) the comparison workload: the bench Cornell box, independent
# samples, box filter, paths of max depth 4 and direct lighting.
BENCH_SCENE := ../shared/scenes/bench/cornell.gltf
BENCH_OPTS  := --width 512 --height 512 --spp 64 --sampler random --filter box
bench: deps strata
	./strata bench --width 512 --height 512 --spp 64 --integrator path
	./strata bench --width 512 --height 512 --spp 64 --integrator direct
	@if [ -f $(BENCH_SCENE) ]; then \
	  ./strata bench $(BENCH_SCENE) $(BENCH_OPTS) --integrator path --max-depth 4 && \
	  ./strata bench $(BENCH_SCENE) $(BENCH_OPTS) --integrator direct; \
	else echo "bench: $(BENCH_SCENE) not found; the comparison workload is skipped"; fi

# The README's pictures, each made by its one line in tools/make_pictures.sh
# (tests/test_pictures.sh checks that a few of them are up to date).
pictures: deps strata
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
