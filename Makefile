# libc4gopen: one Makefile drives everything. Out-of-tree: make BUILD=/some/dir
#   make            library (static + shared) and tools
#   make check      every test and quality gate (installs missing deps first)
#   make demo       a real session on loopback, printed
#   make replay-fixtures  regenerate the capture fixtures in fixtures/replay
#   make replay-golden    rewrite their expected summaries (fixtures/replay/golden; review the diff)
#   make bench      benchmarks with an in-run baseline
#   make coverage   line/branch coverage of lib/ (gated)
#   make fuzz       bounded libFuzzer runs (FUZZ_SECONDS each, default 15; make check: 5)
#   make install    PREFIX=/usr/local DESTDIR=
#   make wireshark-install-user   the Wireshark dissector into ~/.local/lib/wireshark/plugins

BUILD ?= build
PREFIX ?= /usr/local
DESTDIR ?=
# Lua plugin folders of Wireshark (docs/wireshark.md): system-wide under the prefix, and the
# per-user one Wireshark always searches (`tshark -G folders`, "Personal Lua Plugins").
WIRESHARK_PLUGIN_DIR ?= $(PREFIX)/lib/wireshark/plugins
WIRESHARK_USER_PLUGIN_DIR ?= $(HOME)/.local/lib/wireshark/plugins
# bash-completion loads a command's completion from this folder by the command's name
BASH_COMPLETION_DIR ?= $(PREFIX)/share/bash-completion/completions
FUZZ_SECONDS ?= 15
CLANG ?= clang
CXX ?= g++
ARM_CC ?= arm-none-eabi-gcc

VERSION := $(shell sed -n 's/^\#define C4G_VERSION_STRING "\(.*\)"/\1/p' include/c4gopen_base.h)
MAJOR := $(firstword $(subst ., ,$(VERSION)))
SONAME := libc4gopen.so.$(MAJOR)

# Make's built-in CC=cc defeats "CC ?= gcc": detect GCC from its banner.
IS_GCC := $(shell $(CC) --version 2>/dev/null | grep -c 'Free Software Foundation')

WARN_LIB := -Wall -Wextra -Werror -Wconversion -Wsign-conversion -Wdouble-promotion \
  -Wfloat-equal -Wundef -Wshadow -Wcast-qual -Wcast-align -Wswitch-enum -Wswitch-default \
  -Wstrict-prototypes -Wmissing-prototypes -Wmissing-declarations -Wredundant-decls \
  -Wnested-externs -Wold-style-definition -Wbad-function-cast -Wvla -Wwrite-strings \
  -Wformat=2 -Wnull-dereference -Wtype-limits -fno-common
WARN_GCC := -Wlogical-op -Wduplicated-cond -Wduplicated-branches -Wjump-misses-init \
  -Wcast-align=strict -Wstack-usage=2048
ifeq ($(IS_GCC),0)
WARN_GCC :=
endif
LIB_CFLAGS := -std=c99 -pedantic-errors $(WARN_LIB) $(WARN_GCC) -Iinclude
OPT ?= -O2
CFLAGS ?= -g
TOOL_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -pedantic -Wall -Wextra \
  -Werror -Wshadow -Wstrict-prototypes -Wvla -Iinclude
TOOL_CXXFLAGS := -std=c++17 -pedantic -Wall -Wextra -Werror -Iinclude

LIB_SRCS := $(sort $(wildcard lib/*/*.c))
LIB_HDRS := $(wildcard include/*.h) $(wildcard lib/*.h lib/*/*.h)
LIB_OBJS := $(LIB_SRCS:%.c=$(BUILD)/obj/%.o)
LIB_PICS := $(LIB_SRCS:%.c=$(BUILD)/pic/%.o)
STATIC := $(BUILD)/lib/libc4gopen.a
SHARED := $(BUILD)/lib/libc4gopen.so.$(VERSION)

# Tool helpers that tests, benches and fuzz targets also need (plain C99, no dependencies):
# the manual's fixtures and the CSV text of monitoring records. Not in the RT library.
HELPER_SRCS := tools/common/c4g_fixtures.c tools/common/c4g_csv.c

UNIT_SRCS := $(sort $(wildcard tests/test_*.c))
UNIT_BINS := $(UNIT_SRCS:tests/%.c=$(BUILD)/tests/%)
FUZZ_SRCS := $(sort $(wildcard tests/fuzz/fuzz_*.c))
FUZZ_NAMES := $(FUZZ_SRCS:tests/fuzz/%.c=%)

# Tools: every directory tools/NAME becomes $(BUILD)/bin/NAME. tools/NAME/tool.mk may
# set NAME_LDLIBS; C++ sources (*.cpp) link with $(CXX).
TOOL_NAMES := $(notdir $(patsubst %/,%,$(dir $(wildcard tools/*/*.c tools/*/*.cpp))))
TOOL_NAMES := $(sort $(TOOL_NAMES))
-include $(wildcard tools/*/tool.mk)
TOOL_BINS := $(TOOL_NAMES:%=$(BUILD)/bin/%)
COMMON_TOOL_SRCS := $(wildcard tools/common/*.c)
TOOL_NAMES := $(filter-out common,$(TOOL_NAMES))
TOOL_BINS := $(TOOL_NAMES:%=$(BUILD)/bin/%)

DEPS_STAMP := $(BUILD)/.deps-ok

.PHONY: e2e-helpers all lib tools man check demo bench coverage fuzz install uninstall clean deps \
  unit sanitize valgrind audit cross qemu-smoke static-analysis cppcheck misra clang-tidy analyzer \
  e2e ident-accuracy docs-examples fuzz-build complexity nodiscard replay-fixtures replay-golden wireshark-install-user

all: lib tools man

deps: $(DEPS_STAMP)
$(DEPS_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	@sh scripts/deps.sh
	@touch $@

lib: $(STATIC) $(SHARED) $(BUILD)/lib/c4gopen.pc

$(BUILD)/obj/%.o: %.c $(LIB_HDRS) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	@echo "  CC      $@"; $(CC) $(LIB_CFLAGS) $(OPT) $(CFLAGS) -c $< -o $@

$(BUILD)/pic/%.o: %.c $(LIB_HDRS) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	@echo "  CC      $@"; $(CC) $(LIB_CFLAGS) $(OPT) $(CFLAGS) -fPIC -c $< -o $@

$(STATIC): $(LIB_OBJS)
	@mkdir -p $(@D)
	rm -f $@
	ar rcs $@ $^

$(SHARED): $(LIB_PICS)
	@mkdir -p $(@D)
	$(CC) -shared -Wl,-soname,$(SONAME) -o $@ $^ -lm
	ln -sf libc4gopen.so.$(VERSION) $(BUILD)/lib/$(SONAME)
	ln -sf $(SONAME) $(BUILD)/lib/libc4gopen.so

$(BUILD)/lib/c4gopen.pc: scripts/c4gopen.pc.in include/c4gopen.h
	@mkdir -p $(@D)
	sed -e 's|@PREFIX@|$(PREFIX)|g' -e 's|@VERSION@|$(VERSION)|g' $< > $@

# ---- tools
tools: $(TOOL_BINS)

# tools/common/*.c: an archive, so each tool links only the shared pieces it uses
TOOLCOMMON := $(BUILD)/lib/libtoolcommon.a
$(TOOLCOMMON): $(COMMON_TOOL_SRCS:%.c=$(BUILD)/tobj/%.o)
	@mkdir -p $(@D)
	rm -f $@
	ar rcs $@ $^

define tool_rule
$(1)_CSRCS := $$(wildcard tools/$(1)/*.c) $$($(1)_EXTRA_CSRCS)
$(1)_CXXSRCS := $$(wildcard tools/$(1)/*.cpp)
$(1)_OBJS := $$($(1)_CSRCS:%.c=$$(BUILD)/tobj/%.o) $$($(1)_CXXSRCS:%.cpp=$$(BUILD)/tobj/%.o)
$$(BUILD)/bin/$(1): $$($(1)_OBJS) $$(TOOLCOMMON) $$(STATIC)
	@mkdir -p $$(@D)
	$$(if $$($(1)_CXXSRCS),$$(CXX),$$(CC)) -o $$@ $$($(1)_OBJS) $$(TOOLCOMMON) $$(STATIC) $$($(1)_LDLIBS) -lm
endef
$(foreach t,$(TOOL_NAMES),$(eval $(call tool_rule,$(t))))

$(BUILD)/tobj/%.o: %.c $(LIB_HDRS) $(wildcard tools/*/*.h) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(CC) $(TOOL_CFLAGS) -Itools/common $(OPT) $(CFLAGS) -c $< -o $@

$(BUILD)/tobj/%.o: %.cpp $(LIB_HDRS) $(wildcard tools/*/*.h tools/*/*.hpp) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(CXX) $(TOOL_CXXFLAGS) $($(word 2,$(subst /, ,$<))_CXXFLAGS) -Itools/common $(OPT) -g -c $< -o $@

# ---- man pages: docs/man/NAME.scd (scdoc) with each tool's option list and examples
# taken from its own --help (scripts/man-page.py), so page and tool cannot disagree
MAN_SRCS := $(sort $(wildcard docs/man/*.scd))
MAN_PAGES := $(MAN_SRCS:docs/man/%.scd=$(BUILD)/man/%)
man: $(MAN_PAGES)
$(BUILD)/man/%: docs/man/%.scd scripts/man-page.py $(TOOL_BINS) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	@echo "  MAN     $@"; python3 scripts/man-page.py $< $(BUILD)/bin > $@.scd && scdoc < $@.scd > $@

# ---- unit tests (CMocka)
# Tests of tool parsers #include the tool sources they test (tools/ is not in the
# library), so every test sees tools/common and links inih.
TEST_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Wall -Wextra -Werror -Iinclude \
  -Itools/common -g
TEST_LIBS := -lcmocka -linih -lpcap -lm
$(BUILD)/tests/%: tests/%.c $(STATIC) $(wildcard tests/*.h) $(wildcard tools/*/*.c tools/*/*.h)
	@mkdir -p $(@D)
	$(CC) $(TEST_CFLAGS) -DFIXTURES_DIR='"$(CURDIR)/fixtures"' \
	  -o $@ $< $(HELPER_SRCS) $(STATIC) $(TEST_LIBS)

unit: $(UNIT_BINS)
	@sh scripts/run-tests.sh unit $(UNIT_BINS)

# ---- ASan + UBSan build of the unit tests (library compiled in)
# The library and helpers are compiled once per flavour (not once per test), and every
# step is a make target, so `make -jN` builds them in parallel.
SAN_FLAGS := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
SAN_OBJS := $(LIB_SRCS:%.c=$(BUILD)/san/obj/%.o) $(HELPER_SRCS:%.c=$(BUILD)/san/obj/%.o)
$(BUILD)/san/obj/%.o: %.c $(LIB_HDRS) $(wildcard tools/common/*.h) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(CLANG) $(TEST_CFLAGS) $(SAN_FLAGS) -c $< -o $@
$(BUILD)/san/test_%: tests/test_%.c $(SAN_OBJS) $(wildcard tests/*.h) $(wildcard tools/*/*.c tools/*/*.h)
	@mkdir -p $(@D)
	$(CLANG) $(TEST_CFLAGS) $(SAN_FLAGS) -DFIXTURES_DIR='"$(CURDIR)/fixtures"' -o $@ $< $(SAN_OBJS) $(TEST_LIBS)
sanitize: $(UNIT_SRCS:tests/%.c=$(BUILD)/san/%)
	@sh scripts/run-tests.sh sanitize $^

# ---- the unit tests under valgrind memcheck (uninitialised reads ASan does not see)
# (one target per binary, so `make -jN valgrind` runs N at a time: their temporary files are
# mkstemp's, and no unit test binds a port)
valgrind: $(UNIT_BINS:$(BUILD)/tests/%=valgrind-run-%)
	@echo "valgrind: $(words $(UNIT_BINS)) test binaries clean"
valgrind-run-%: $(BUILD)/tests/%
	@mkdir -p $(BUILD)/valgrind
	@valgrind -q --error-exitcode=1 --leak-check=full $< >/dev/null 2>$(BUILD)/valgrind/$*.log || \
	  { cat $(BUILD)/valgrind/$*.log; echo "valgrind: $< FAILED"; exit 1; }

# ---- coverage of lib/ (gcov + lcov): 100% lines, >= 95% branches
COV_LINES ?= 100
COV_BRANCHES ?= 95
COV_FLAGS := $(TEST_CFLAGS) -O0 --coverage -DNDEBUG
COV_OBJS := $(LIB_SRCS:%.c=$(BUILD)/cov/obj/%.o) $(HELPER_SRCS:%.c=$(BUILD)/cov/obj/%.o)
$(BUILD)/cov/obj/%.o: %.c $(LIB_HDRS) $(wildcard tools/common/*.h) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	gcc $(COV_FLAGS) -c $< -o $@
$(BUILD)/cov/test_%: tests/test_%.c $(COV_OBJS) $(wildcard tests/*.h) $(wildcard tools/*/*.c tools/*/*.h)
	@mkdir -p $(@D)
	gcc $(COV_FLAGS) -DFIXTURES_DIR='"$(CURDIR)/fixtures"' -o $@ $< $(COV_OBJS) $(TEST_LIBS)
# the counts of every test binary add up in the shared objects' .gcda files: start from zero
coverage: $(UNIT_SRCS:tests/%.c=$(BUILD)/cov/%)
	@find $(BUILD)/cov -name '*.gcda' -delete; rm -f $(BUILD)/cov/*.info
	@cd $(BUILD)/cov && for t in $(UNIT_SRCS:tests/%.c=%); do ./$$t >/dev/null 2>&1 || { echo "coverage: $$t failed"; exit 1; }; done
	@sh scripts/coverage-gate.sh $(BUILD)/cov $(COV_LINES) $(COV_BRANCHES)

# ---- fuzzing (libFuzzer via clang), bounded
# The library is compiled once with the fuzzer's coverage instrumentation. Targets of
# tool parsers also compile the tool sources named in FUZZ_TOOL_<name> (the parsers
# take a buffer in memory) and link inih.
FUZZ_SAN := -g -O1 -fsanitize=address,undefined -fno-sanitize-recover=all
FUZZ_LIB_OBJS := $(LIB_SRCS:%.c=$(BUILD)/fuzz/obj/%.o) $(HELPER_SRCS:%.c=$(BUILD)/fuzz/obj/%.o)
FUZZ_TF := tools/common/c4g_textfile.c
FUZZ_TOOL_fuzz_scenario := tools/c4g-sim/scenario.c $(FUZZ_TF)
FUZZ_TOOL_fuzz_sim_ini := tools/c4g-sim/config.c tools/c4g-sim/model.c $(FUZZ_TF)
FUZZ_FFM := tools/common/c4g_ffmodel.c tools/common/c4g_ffmodel_load.c
FUZZ_TOOL_fuzz_traj := tools/common/c4g_srv_files.c $(FUZZ_FFM) $(FUZZ_TF)
FUZZ_TOOL_fuzz_ff := tools/common/c4g_srv_files.c $(FUZZ_FFM) $(FUZZ_TF)
FUZZ_TOOL_fuzz_ffmodel := $(FUZZ_FFM) $(FUZZ_TF)
FUZZ_TOOL_fuzz_server_ini := tools/common/c4g_srv_opts.c tools/common/c4g_cli.c $(FUZZ_TF)
FUZZ_TOOL_fuzz_cli_ini := tools/cell-cli/cli_config.c tools/common/cell_common.c $(FUZZ_TF)
FUZZ_TOOL_fuzz_cli_cmd := tools/cell-cli/cli_cmd.c tools/common/cell_common.c $(FUZZ_TF)
FUZZ_TOOL_fuzz_canopen_ini := tools/common/c4g_co_config.c $(FUZZ_TF)
FUZZ_TOOL_fuzz_capture := tools/c4g-replay/capture.c tools/c4g-replay/analyze.c \
  tools/common/c4g_ctrlside.c tools/common/c4g_hist.c
FUZZ_LIBS_fuzz_capture := -lpcap
FUZZ_TOOL_INC := -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Itools/common -Itools/c4g-sim \
  -Itools/cell-cli -Itools/c4g-replay

.SECONDARY: $(FUZZ_LIB_OBJS) $(SAN_OBJS) $(COV_OBJS)
$(BUILD)/fuzz/obj/%.o: %.c $(LIB_HDRS) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	@echo "  FUZZCC  $@"; $(CLANG) -std=c99 -Iinclude $(FUZZ_SAN) -fsanitize=fuzzer-no-link -c $< -o $@

$(BUILD)/fuzz/fuzz_%: tests/fuzz/fuzz_%.c $(FUZZ_LIB_OBJS) $(wildcard tests/fuzz/*.h) \
    $(wildcard tools/*/*.c tools/*/*.h) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	@echo "  FUZZLD  $@"; $(CLANG) -std=c99 -Iinclude -Itools/common $(if $(FUZZ_TOOL_$(@F)),$(FUZZ_TOOL_INC)) \
	  $(FUZZ_SAN) -fsanitize=fuzzer -o $@ $< $(FUZZ_TOOL_$(@F)) $(FUZZ_LIB_OBJS) \
	  $(if $(FUZZ_TOOL_$(@F)),-linih) $(FUZZ_LIBS_$(@F)) -lm

fuzz-build: $(FUZZ_NAMES:%=$(BUILD)/fuzz/%)
# one target per run, so `make -jN fuzz` runs N fuzzers at a time
fuzz: $(FUZZ_NAMES:%=fuzz-run-%)
fuzz-run-%: $(BUILD)/fuzz/%
	@sh scripts/run-fuzz.sh $(BUILD)/fuzz $(FUZZ_SECONDS) $*

# ---- symbol audit, cross builds, qemu smoke test
audit: $(STATIC)
	@sh scripts/check-symbols.sh nm $(STATIC)

ARM_FLAGS := -std=c99 -pedantic-errors $(WARN_LIB) -Iinclude -Os -ffreestanding
cross: | $(DEPS_STAMP)
	@rm -rf $(BUILD)/arm $(BUILD)/armbe && mkdir -p $(BUILD)/arm $(BUILD)/armbe
	@set -e; for f in $(LIB_SRCS); do \
	  $(ARM_CC) $(ARM_FLAGS) -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -c $$f -o $(BUILD)/arm/$$(basename $$f .c).o; \
	  $(ARM_CC) $(ARM_FLAGS) -mcpu=cortex-r5 -marm -mbig-endian -c $$f -o $(BUILD)/armbe/$$(basename $$f .c).o; done
	@arm-none-eabi-ar rcs $(BUILD)/arm/libc4gopen.a $(BUILD)/arm/*.o
	@arm-none-eabi-ar rcs $(BUILD)/armbe/libc4gopen.a $(BUILD)/armbe/*.o
	@sh scripts/check-symbols.sh arm-none-eabi-nm $(BUILD)/arm/libc4gopen.a
	@sh scripts/check-symbols.sh arm-none-eabi-nm $(BUILD)/armbe/libc4gopen.a
	@echo "cross: cortex-m4 thumb size:"; arm-none-eabi-size -t $(BUILD)/arm/libc4gopen.a | tail -1
	@echo "cross: cortex-r5 big-endian OK"

qemu-smoke: | $(DEPS_STAMP)
	@mkdir -p $(BUILD)/qemu
	$(ARM_CC) -std=c99 -O1 -Iinclude -marm -mcpu=arm926ej-s --specs=rdimon.specs \
	  -DFIXTURE_INIT='"$(CURDIR)/fixtures/vectors/init-fig10-1.bin"' \
	  -Itools/common tests/target/target_smoke.c $(LIB_SRCS) $(HELPER_SRCS) -o $(BUILD)/qemu/target_smoke.elf -lm
	qemu-arm $(BUILD)/qemu/target_smoke.elf
	$(ARM_CC) -std=c99 -O2 -Iinclude -marm -mcpu=cortex-r5 -mbig-endian -mbe8 -ffreestanding -nostdlib \
	  -static -Wl,--be8 tests/target/target_be_codec.c lib/wire/c4g_codec.c lib/wire/c4g_modes.c \
	  -o $(BUILD)/qemu/target_be_codec.elf
	qemu-armeb $(BUILD)/qemu/target_be_codec.elf && echo "qemu-smoke: big-endian codec OK (qemu-armeb)"

# ---- static analysis
cppcheck: | $(DEPS_STAMP)
	@mkdir -p $(BUILD)
	cppcheck --quiet --std=c99 --language=c --enable=warning,style,performance,portability \
	  --inline-suppr --error-exitcode=2 --suppress=missingIncludeSystem -Iinclude $(LIB_SRCS)
	@echo "cppcheck: clean"
misra: | $(DEPS_STAMP)
	@mkdir -p $(BUILD)
	@rm -f $(BUILD)/misra.txt
	@mkdir -p $(BUILD)/cppcheck-misra
	cppcheck --quiet --std=c99 --language=c --addon=misra --inline-suppr \
	  --cppcheck-build-dir=$(BUILD)/cppcheck-misra \
	  --suppressions-list=scripts/cppcheck-misra.supp -Iinclude --error-exitcode=3 \
	  --output-file=$(BUILD)/misra.txt $(LIB_SRCS)
	@if [ -s $(BUILD)/misra.txt ]; then cat $(BUILD)/misra.txt; echo "misra: findings above (see docs/misra-deviations.md)"; exit 1; fi
	@echo "misra: clean (deviations: docs/misra-deviations.md)"
clang-tidy: | $(DEPS_STAMP)
	clang-tidy --quiet $(LIB_SRCS) -- -std=c99 -Iinclude
	@echo "clang-tidy: clean"
analyzer: | $(DEPS_STAMP)
	@mkdir -p $(BUILD)/fanalyzer
	@set -e; for f in $(LIB_SRCS); do gcc -std=c99 -fanalyzer -Werror -Iinclude -c $$f -o $(BUILD)/fanalyzer/$$(basename $$f .c).o; done
	@echo "analyzer: gcc -fanalyzer clean"
# Cognitive complexity of the tools and tests (laxer than the library's 25, set in
# .clang-tidy): functions of one job each, mains that only wire the parts together.
TOOL_COMPLEXITY ?= 40
TEST_COMPLEXITY ?= 90
CPLX_INC := -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -DFIXTURES_DIR=\"\" -Iinclude -Itools/common \
  -Itools/c4g-sim -Itools/c4g-server -Itools/cell-cli -Itools/cell-sim -Itools/c4g-replay
complexity: | $(DEPS_STAMP)
	@sh scripts/complexity.sh $(TOOL_COMPLEXITY) "$(CPLX_INC)" $(sort $(wildcard tools/*/*.c))
	@sh scripts/complexity.sh $(TEST_COMPLEXITY) "$(CPLX_INC)" $(UNIT_SRCS) $(FUZZ_SRCS)
# Statuses nobody reads: clang honours C4G_NODISCARD (and a deliberate (void) cast).
nodiscard: | $(DEPS_STAMP)
	@set -e; for f in $(sort $(wildcard tools/*/*.c)) examples/*.c docs/examples/*.c bench/*.c $(UNIT_SRCS) $(FUZZ_SRCS); do \
	  $(CLANG) $(CPLX_INC) -fsyntax-only -Werror=unused-result $$f; done
	@echo "nodiscard: every status is used or deliberately dropped"
static-analysis: cppcheck misra clang-tidy analyzer complexity nodiscard

# ---- end-to-end tests (real processes, loopback) and doc examples
e2e: all e2e-helpers
	@sh scripts/run-e2e.sh $(BUILD)
# The e2e tests' C helpers (tests/e2e/helpers/*.c) against the static library, in $(BUILD)/e2e;
# a few also take a tool's own reader or writer (their extra sources below).
E2E_HELPER_SRCS := $(sort $(wildcard tests/e2e/helpers/*.c))
E2E_HELPERS := $(patsubst tests/e2e/helpers/%.c,$(BUILD)/e2e/%,$(E2E_HELPER_SRCS))
E2E_HELPER_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra -Werror \
  -Iinclude -Itools/common -Itools/c4g-replay
E2E_EXTRA_cap_payloads := tools/c4g-replay/capture.c -lpcap
E2E_EXTRA_forge_capture := tools/common/c4g_pcap.c tools/common/c4g_fixtures.c -lpcap
E2E_EXTRA_ctrl_stub := tools/common/c4g_fixtures.c
e2e-helpers: $(E2E_HELPERS)
$(BUILD)/e2e/%: tests/e2e/helpers/%.c $(STATIC)
	@mkdir -p $(@D)
	$(CC) $(E2E_HELPER_CFLAGS) -o $@ $< $(filter %.c,$(E2E_EXTRA_$*)) $(STATIC) $(filter -l%,$(E2E_EXTRA_$*)) -lm

# ---- c4g-ident's accuracy against c4g-sim's axis model, in-process (tests/ident)
IDENT_ACC := $(BUILD)/tests/ident-accuracy
IDENT_SEEDS ?= 6
# c4g-ident's own objects (built for the tool), the harness compiled beside them
IDENT_TOOL_OBJS := $(addprefix $(BUILD)/tobj/tools/c4g-ident/,signal.o fit.o excite.o)
IDENT_OBJS := $(BUILD)/tests/ident-obj/accuracy.o $(BUILD)/tests/ident-obj/simgen.o \
  $(BUILD)/tests/ident-obj/model.o
$(BUILD)/tests/ident-obj/%.o: tests/ident/%.cpp tests/ident/simgen.hpp tools/c4g-ident/ident.hpp \
  tools/c4g-ident/excite.hpp tools/c4g-sim/model.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(CXX) $(TOOL_CXXFLAGS) -isystem /usr/include/eigen3 -Itools/c4g-ident -Itools/c4g-sim -O2 -g -c $< -o $@
$(BUILD)/tests/ident-obj/model.o: tools/c4g-sim/model.c tools/c4g-sim/model.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(CC) $(TOOL_CFLAGS) -O2 -c $< -o $@
$(IDENT_ACC): $(IDENT_OBJS) $(IDENT_TOOL_OBJS)
	$(CXX) -o $@ $^ -lceres -lglog -lpthread -lm
ident-accuracy: $(IDENT_ACC)
	@echo "== c4g-ident accuracy ($(IDENT_SEEDS) seeds per case; make bench runs 30)"
	@$(IDENT_ACC) --seeds $(IDENT_SEEDS) --gate
docs-examples: $(STATIC)
	@sh scripts/docs-examples.sh $(BUILD)

# ---- the two README commands
CHECK_GATES := all unit ident-accuracy sanitize valgrind coverage audit static-analysis cross \
  qemu-smoke docs-examples e2e fuzz
# Each gate builds with one job per core unless the caller chose -j; the fuzz gate replays
# every seed and fuzzes CHECK_FUZZ_SECONDS per target (make bench: FUZZ_SECONDS each).
CHECK_JOBS ?= $(if $(filter -j%,$(MAKEFLAGS)),,-j$(shell nproc 2>/dev/null || echo 1))
CHECK_FUZZ_SECONDS ?= 5
check: $(DEPS_STAMP)
	@sh scripts/check.sh "$(MAKE) --no-print-directory $(CHECK_JOBS) FUZZ_SECONDS=$(CHECK_FUZZ_SECONDS)" $(CHECK_GATES)

demo: all
	@sh scripts/demo.sh $(BUILD)

# c4g-replay's capture fixtures (fixtures/replay/README.md); real runs on 127.0.0.1
replay-fixtures: lib tools
	@sh scripts/make-replay-fixtures.sh $(BUILD)

replay-golden: tools
	sh scripts/make-replay-golden.sh $(BUILD)

bench: $(DEPS_STAMP)
	@$(MAKE) --no-print-directory all
	@$(MAKE) --no-print-directory ident-accuracy IDENT_SEEDS=30
	@sh scripts/bench.sh $(BUILD)
	@$(MAKE) --no-print-directory fuzz

# ---- install
install: lib tools man
	install -d $(DESTDIR)$(PREFIX)/include $(DESTDIR)$(PREFIX)/lib/pkgconfig $(DESTDIR)$(PREFIX)/bin \
	  $(DESTDIR)$(PREFIX)/share/doc/libc4gopen
	install -m 644 include/*.h $(DESTDIR)$(PREFIX)/include/
	install -m 644 $(STATIC) $(DESTDIR)$(PREFIX)/lib/
	install -m 755 $(SHARED) $(DESTDIR)$(PREFIX)/lib/
	ln -sf libc4gopen.so.$(VERSION) $(DESTDIR)$(PREFIX)/lib/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(PREFIX)/lib/libc4gopen.so
	sed -e 's|@PREFIX@|$(PREFIX)|g' -e 's|@VERSION@|$(VERSION)|g' scripts/c4gopen.pc.in \
	  > $(DESTDIR)$(PREFIX)/lib/pkgconfig/c4gopen.pc
	$(if $(TOOL_BINS),install -m 755 $(TOOL_BINS) $(DESTDIR)$(PREFIX)/bin/)
	install -m 644 docs/*.md README.md LICENSE $(DESTDIR)$(PREFIX)/share/doc/libc4gopen/
	install -d $(DESTDIR)$(PREFIX)/share/doc/libc4gopen/examples
	install -m 644 examples/mode4_loop.c examples/README.md $(DESTDIR)$(PREFIX)/share/doc/libc4gopen/examples/
	sed 's|/usr/local/bin/|$(PREFIX)/bin/|' examples/c4g-server.service \
	  > $(DESTDIR)$(PREFIX)/share/doc/libc4gopen/examples/c4g-server.service
	install -d $(DESTDIR)$(PREFIX)/share/man/man1 $(DESTDIR)$(PREFIX)/share/man/man3
	install -m 644 $(filter %.1,$(MAN_PAGES)) $(DESTDIR)$(PREFIX)/share/man/man1/
	install -m 644 $(filter %.3,$(MAN_PAGES)) $(DESTDIR)$(PREFIX)/share/man/man3/
	install -d $(DESTDIR)$(BASH_COMPLETION_DIR)
	install -m 644 scripts/completion/c4gopen.bash $(DESTDIR)$(BASH_COMPLETION_DIR)/c4g-server
	$(foreach t,$(filter-out c4g-server,$(TOOL_NAMES)),ln -sf c4g-server $(DESTDIR)$(BASH_COMPLETION_DIR)/$(t);)
	install -d $(DESTDIR)$(WIRESHARK_PLUGIN_DIR)
	install -m 644 tools/wireshark/c4gopen.lua $(DESTDIR)$(WIRESHARK_PLUGIN_DIR)/
uninstall:
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/include/,$(notdir $(wildcard include/*.h)))
	rm -f $(DESTDIR)$(PREFIX)/lib/libc4gopen.a $(DESTDIR)$(PREFIX)/lib/libc4gopen.so*
	rm -f $(DESTDIR)$(PREFIX)/lib/pkgconfig/c4gopen.pc
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/bin/,$(TOOL_NAMES))
	rm -rf $(DESTDIR)$(PREFIX)/share/doc/libc4gopen
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/share/man/man1/,$(notdir $(filter %.1,$(MAN_PAGES))))
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/share/man/man3/,$(notdir $(filter %.3,$(MAN_PAGES))))
	rm -f $(addprefix $(DESTDIR)$(BASH_COMPLETION_DIR)/,$(TOOL_NAMES))
	rm -f $(DESTDIR)$(WIRESHARK_PLUGIN_DIR)/c4gopen.lua
wireshark-install-user:
	install -d $(WIRESHARK_USER_PLUGIN_DIR)
	install -m 644 tools/wireshark/c4gopen.lua $(WIRESHARK_USER_PLUGIN_DIR)/

clean:
	rm -rf $(BUILD)
