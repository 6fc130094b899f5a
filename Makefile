# libc4gopen: one Makefile drives everything. Out-of-tree: make BUILD=/some/dir
#   make lib        the library (static + shared, pkg-config file): needs only a C compiler
#   make            the library, the tools whose libraries are present, their man pages
#   make check      every test and quality gate (installs missing deps first)
#   make demo       a real session on loopback, printed
#   make replay-fixtures  regenerate the capture fixtures in fixtures/replay
#   make replay-golden    rewrite their expected summaries (fixtures/replay/golden; review the diff)
#   make bench      benchmarks with an in-run baseline
#   make coverage   line/branch coverage of lib/ (gated)
#   make fuzz       bounded libFuzzer runs (FUZZ_SECONDS each, default 15; make check: 5)
#   make install    PREFIX=/usr/local DESTDIR=  (runs ldconfig for the default prefix as root)
#   make wireshark-install-user   the Wireshark dissector into ~/.local/lib/wireshark/plugins
# Dependencies come in groups (scripts/deps.sh lib|tools|check): each target checks only its
# own group. As root the missing packages are installed; as another user they are named,
# `make` builds what the machine can and `make check` stops.

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
LIB_CFLAGS := -std=c99 -pedantic-errors $(WARN_LIB) $(WARN_GCC) -Iinclude -ffunction-sections -fdata-sections
OPT ?= -O2
CFLAGS ?= -g
TOOL_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -pedantic -Wall -Wextra \
  -Werror -Wshadow -Wstrict-prototypes -Wvla
TOOL_CXXFLAGS := -std=c++17 -pedantic -Wall -Wextra -Werror

# Three archives (docs/architecture.md):
#   libc4gopen       lib/{wire,engine,loop,cell,canopen}: the real-time library (installed)
#   libc4gopen-sim   lib/sim: the controller model, CANopen slaves, fixtures; pure like the core
#   libc4gopen-host  lib/host: POSIX I/O for the tools (sockets, clocks, files, pcap, CLI)
# The two pure archives pass the same gates (strict flags, MISRA, clang-tidy, cross builds,
# coverage); every tool is tools/NAME/*.c: its main file plus an archive of the rest, which
# its tests and fuzz targets link.
CORE_DIRS := wire engine loop cell canopen dyn
LIB_SRCS := $(sort $(foreach d,$(CORE_DIRS),$(wildcard lib/$(d)/*.c)))
SIM_SRCS := $(sort $(wildcard lib/sim/*.c))
HOST_SRCS := $(sort $(wildcard lib/host/*.c))
# the sources every pure gate covers (strict flags, MISRA, clang-tidy, analyzer, cross, coverage)
PURE_SRCS := $(LIB_SRCS) $(SIM_SRCS)
LIB_HDRS := $(wildcard include/*.h) $(wildcard lib/*.h) $(foreach d,$(CORE_DIRS),$(wildcard lib/$(d)/*.h))
SIM_HDRS := $(wildcard lib/sim/*.h)
HOST_HDRS := $(wildcard lib/host/*.h)
LIB_OBJS := $(LIB_SRCS:%.c=$(BUILD)/obj/%.o)
LIB_PICS := $(LIB_SRCS:%.c=$(BUILD)/pic/%.o)
STATIC := $(BUILD)/lib/libc4gopen.a
SHARED := $(BUILD)/lib/libc4gopen.so.$(VERSION)
SIM_LIB := $(BUILD)/lib/libc4gopen-sim.a
HOST_LIB := $(BUILD)/lib/libc4gopen-host.a
ARCH_INC := -Iinclude -Ilib/sim -Ilib/host

# Tools: every directory tools/NAME becomes $(BUILD)/bin/NAME. tools/NAME/tool.mk may set
# NAME_LDLIBS, NAME_CPPFLAGS and NAME_USES (other tools' archives it links); C++ sources
# link with $(CXX). The file with main() is the tool's MAIN; the rest is its archive.
TOOL_NAMES := $(sort $(notdir $(patsubst %/,%,$(dir $(wildcard tools/*/*.c tools/*/*.cpp)))))
-include $(wildcard tools/*/tool.mk)
TOOL_BINS = $(TOOLS_BUILT:%=$(BUILD)/bin/%)
C_TOOLS := $(sort $(notdir $(patsubst %/,%,$(dir $(wildcard tools/*/*.c)))))
tool_main = $(shell grep -l '^int main.int argc' $(wildcard tools/$(1)/*.c tools/$(1)/*.cpp) 2>/dev/null)
tool_srcs = $(filter-out $(call tool_main,$(1)),$(wildcard tools/$(1)/*.c))
TOOL_INC := $(foreach t,$(C_TOOLS),-Itools/$(t))
TOOL_LIB_LIBS := -linih -lpcap -ljansson -ledit -lmujoco -lpthread -lm

# Which tools this machine can build: each library a tool links is a header the C compiler
# must find (HEADER:PACKAGE, the Debian package as scripts/deps.sh names it); every
# tool links the host archive (pcap, inih, SocketCAN); a C++ tool needs $(CXX). A tool whose
# part is missing is left out of `make`, named with its packages.
CC_INC_DIRS := $(shell $(CC) -E -Wp,-v -x c /dev/null 2>&1 >/dev/null | sed -n 's|^ \(/[^ ]*\)$$|\1|p')
LIBHDR_-lpcap := pcap/pcap.h:libpcap-dev
LIBHDR_-linih := ini.h:libinih-dev
LIBHDR_-ljansson := jansson.h:libjansson-dev
LIBHDR_-ledit := histedit.h:libedit-dev
LIBHDR_-lceres := ceres/ceres.h:libceres-dev
LIBHDR_-lmujoco := mujoco/mujoco.h:libmujoco-dev
HOST_NEEDS := pcap/pcap.h:libpcap-dev ini.h:libinih-dev linux/can/raw.h:linux-libc-dev
HAVE_CXX := $(shell command -v $(firstword $(CXX)) 2>/dev/null)
tool_needs = $(sort $(HOST_NEEDS) $(foreach l,$(filter -l%,$($(1)_LDLIBS)),$(LIBHDR_$(l))))
tool_missing = $(strip $(foreach n,$(call tool_needs,$(1)),$(if $(wildcard $(addsuffix /$(firstword \
  $(subst :, ,$(n))),$(CC_INC_DIRS))),,$(lastword $(subst :, ,$(n))))) \
  $(if $(wildcard tools/$(1)/*.cpp),$(if $(HAVE_CXX),,g++)))
TOOLS_SKIPPED := $(strip $(foreach t,$(TOOL_NAMES),$(if $(call tool_missing,$(t)),$(t))))
TOOLS_BUILT := $(filter-out $(TOOLS_SKIPPED),$(TOOL_NAMES))
# man pages: scdoc renders them, python3 fills the option lists in from each tool's --help
HAVE_MAN_TOOLS := $(and $(shell command -v scdoc 2>/dev/null),$(shell command -v python3 2>/dev/null))

UNIT_SRCS := $(sort $(wildcard tests/lib/test_*.c tests/sim/test_*.c tests/host/test_*.c tests/tools/test_*.c))
UNIT_NAMES := $(notdir $(UNIT_SRCS:%.c=%))
UNIT_BINS := $(UNIT_NAMES:%=$(BUILD)/tests/%)
FUZZ_SRCS := $(sort $(wildcard tests/fuzz/fuzz_*.c))
FUZZ_NAMES := $(FUZZ_SRCS:tests/fuzz/%.c=%)

# the QA set (make check, and every gate's own tools); the library needs only deps-lib
DEPS_STAMP := $(BUILD)/.deps-ok
DEPS_LIB_STAMP := $(BUILD)/.deps-lib-ok

.PHONY: all lib tools man check demo bench coverage fuzz install uninstall clean deps deps-lib deps-tools \
  unit sanitize valgrind audit cross qemu-smoke static-analysis cppcheck misra clang-tidy analyzer \
  e2e ident-accuracy docs-examples docs-commands fuzz-build complexity nodiscard replay-fixtures replay-golden wireshark-install-user

all: lib tools man

deps: $(DEPS_STAMP)
$(DEPS_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	@sh scripts/deps.sh check
	@touch $@
deps-lib: $(DEPS_LIB_STAMP)
$(DEPS_LIB_STAMP): scripts/deps.sh
	@mkdir -p $(@D)
	@sh scripts/deps.sh lib
	@touch $@
# The tools' group, checked (as root: installed) before make reads which tools it can build:
# this file is a makefile make remakes, then restarts on, so a tool whose package was just
# installed is built in the same run. A user who is not root gets the packages named.
DEPS_TOOLS_MK := $(BUILD)/.deps-tools.mk
deps-tools:
	@sh scripts/deps.sh tools || true
$(DEPS_TOOLS_MK): scripts/deps.sh
	@mkdir -p $(@D)
	@sh scripts/deps.sh tools || true
	@echo '# scripts/deps.sh tools ran for this build folder' > $@
ifneq ($(filter-out lib deps deps-lib deps-tools clean uninstall wireshark-install-user audit docs-examples,$(or $(MAKECMDGOALS),all)),)
-include $(DEPS_TOOLS_MK)
endif

lib: $(STATIC) $(SHARED) $(BUILD)/lib/c4gopen.pc

$(BUILD)/obj/lib/sim/%.o: lib/sim/%.c $(LIB_HDRS) $(SIM_HDRS) | $(DEPS_LIB_STAMP)
	@mkdir -p $(@D)
	@echo "  CC      $@"; $(CC) $(LIB_CFLAGS) -Ilib/sim $(OPT) $(CFLAGS) -c $< -o $@

$(BUILD)/obj/lib/host/%.o: lib/host/%.c $(LIB_HDRS) $(SIM_HDRS) $(HOST_HDRS) | $(DEPS_LIB_STAMP)
	@mkdir -p $(@D)
	@echo "  CC      $@"; $(CC) $(TOOL_CFLAGS) $(ARCH_INC) $(OPT) $(CFLAGS) -c $< -o $@

$(BUILD)/obj/%.o: %.c $(LIB_HDRS) | $(DEPS_LIB_STAMP)
	@mkdir -p $(@D)
	@echo "  CC      $@"; $(CC) $(LIB_CFLAGS) $(OPT) $(CFLAGS) -c $< -o $@

$(BUILD)/pic/%.o: %.c $(LIB_HDRS) | $(DEPS_LIB_STAMP)
	@mkdir -p $(@D)
	@echo "  CC      $@"; $(CC) $(LIB_CFLAGS) $(OPT) $(CFLAGS) -fPIC -c $< -o $@

# The static archive is one relocatable object whose internal symbols (C4G_INTERNAL) are
# made local: it exports exactly the public headers. Each function has its own section, so
# a program linked with --gc-sections keeps only what it calls.
$(STATIC): $(LIB_OBJS)
	@mkdir -p $(@D)
	@rm -f $@ $(BUILD)/obj/libc4gopen.o
	ld -r -o $(BUILD)/obj/libc4gopen.o $^ && objcopy --localize-hidden $(BUILD)/obj/libc4gopen.o
	ar rcs $@ $(BUILD)/obj/libc4gopen.o
$(SIM_LIB): $(SIM_SRCS:%.c=$(BUILD)/obj/%.o)
	@mkdir -p $(@D)
	@rm -f $@; ar rcs $@ $^
$(HOST_LIB): $(HOST_SRCS:%.c=$(BUILD)/obj/%.o)
	@mkdir -p $(@D)
	@rm -f $@; ar rcs $@ $^

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
ifneq ($(TOOLS_SKIPPED),)
	@$(foreach t,$(TOOLS_SKIPPED),echo "tools: $(t) not built: missing $(call tool_missing,$(t))" >&2;) \
	  echo "tools: sh scripts/deps.sh tools (as root) installs them" >&2
endif
ARCHIVES := $(HOST_LIB) $(SIM_LIB) $(STATIC)

define tool_rule
$(1)_MAIN := $$(call tool_main,$(1))
$(1)_LIB := $$(BUILD)/tools/lib$(1).a
$$($(1)_LIB): $$(patsubst %.c,$$(BUILD)/tobj/%.o,$$(call tool_srcs,$(1)))
	@mkdir -p $$(@D)
	@rm -f $$@; ar rcs $$@ $$^
$(1)_CXXSRCS := $$(filter-out $$($(1)_MAIN),$$(wildcard tools/$(1)/*.cpp))
$(1)_OBJS := $$(patsubst %.c,$$(BUILD)/tobj/%.o,$$(patsubst %.cpp,%.c,$$($(1)_MAIN) $$($(1)_CXXSRCS)))
$$(BUILD)/bin/$(1): $$($(1)_OBJS) $$($(1)_LIB) $$(foreach u,$$($(1)_USES),$$(BUILD)/tools/lib$$(u).a) $$(ARCHIVES)
	@mkdir -p $$(@D)
	$$(if $$(filter %.cpp,$$($(1)_MAIN)),$$(CXX),$$(CC)) -o $$@ $$($(1)_OBJS) $$($(1)_LIB) \
	  $$(foreach u,$$($(1)_USES),$$(BUILD)/tools/lib$$(u).a) $$(ARCHIVES) $$($(1)_LDLIBS) -lm
endef
$(foreach t,$(TOOL_NAMES),$(eval $(call tool_rule,$(t))))

$(BUILD)/tobj/%.o: %.c $(LIB_HDRS) $(SIM_HDRS) $(HOST_HDRS) $(wildcard tools/*/*.h) | $(DEPS_LIB_STAMP)
	@mkdir -p $(@D)
	@echo "  CC      $@"; $(CC) $(TOOL_CFLAGS) $(ARCH_INC) $($(word 2,$(subst /, ,$<))_CPPFLAGS) $(OPT) $(CFLAGS) -c $< -o $@

$(BUILD)/tobj/%.o: %.cpp $(LIB_HDRS) $(HOST_HDRS) $(wildcard tools/*/*.h tools/*/*.hpp) | $(DEPS_LIB_STAMP)
	@mkdir -p $(@D)
	@echo "  CXX     $@"; $(CXX) $(TOOL_CXXFLAGS) $(ARCH_INC) $($(word 2,$(subst /, ,$<))_CXXFLAGS) $(OPT) -g -c $< -o $@

# ---- man pages: docs/man/NAME.scd (scdoc) with each tool's option list and examples
# taken from its own --help (scripts/man-page.py), so page and tool cannot disagree
# A tool's page needs the tool built; without scdoc or python3 no page is made (named).
MAN_SRCS := $(sort $(wildcard docs/man/*.scd))
MAN_ALL := $(MAN_SRCS:docs/man/%.scd=$(BUILD)/man/%)
MAN_PAGES = $(if $(HAVE_MAN_TOOLS),$(filter-out $(TOOLS_SKIPPED:%=$(BUILD)/man/%.1),$(MAN_ALL)))
man: $(MAN_PAGES) $(if $(HAVE_MAN_TOOLS),$(BUILD)/man/fn/.made)
	@$(if $(HAVE_MAN_TOOLS),:,echo "man: no pages made: scdoc and python3 make them (sh scripts/deps.sh tools)" >&2)
$(BUILD)/man/%.1: docs/man/%.1.scd scripts/man-page.py $(BUILD)/bin/%
	@mkdir -p $(@D)
	@echo "  MAN     $@"; python3 scripts/man-page.py $< $(BUILD)/bin > $@.scd && scdoc < $@.scd > $@
$(BUILD)/man/%.3: docs/man/%.3.scd scripts/man-page.py $(wildcard include/*.h)
	@mkdir -p $(@D)
	@echo "  MAN     $@"; python3 scripts/man-page.py $< $(BUILD)/bin > $@.scd && scdoc < $@.scd > $@
# `man c4g_loop_rx`: one .so link per function to the page of its header
MAN_HDR_PAGES = $(filter $(BUILD)/man/c4gopen_%.3,$(MAN_PAGES))
$(BUILD)/man/fn/.made: $(MAN_HDR_PAGES) scripts/man-page.py
	@rm -rf $(@D); mkdir -p $(@D)
	@set -e; for p in $(notdir $(basename $(MAN_HDR_PAGES))); do \
	  for f in $$(python3 scripts/man-page.py --functions include/$$p.h); do \
	    echo ".so man3/$$p.3" > $(@D)/$$f.3; done; done
	@touch $@

# ---- unit tests (CMocka): tests/lib, tests/sim, tests/host, tests/tools mirror the sources
# (tests/README.md). A test links the archives; it includes a .c only to reach a static
# function, and says so. Every flavour below (plain, ASan+UBSan, coverage, libFuzzer) builds
# its own copy of the three archives and of each tool's archive.
TEST_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Wall -Wextra -Werror -Itests $(ARCH_INC) \
  $(TOOL_INC) -g
TEST_LIBS := -lcmocka $(TOOL_LIB_LIBS)
TOOL_C_LIBS = $(foreach t,$(C_TOOLS),$(1)/tools/lib$(t).a)
# What a test links, by its folder ($(1)), in flavour directory $(2): a library test needs
# only the pure archives, so editing a tool relinks only tests/tools and tests/host.
test_archs = $(if $(filter tests/tools/,$(1)),$(call TOOL_C_LIBS,$(2))) \
  $(if $(filter tests/tools/ tests/host/,$(1)),$(2)/lib/libc4gopen-host.a) \
  $(2)/lib/libc4gopen-sim.a $(2)/lib/libc4gopen.a
# unit_test SRC FLAVOUR_DIR COMPILER_AND_FLAGS
define unit_test
$(2)/tests/$(notdir $(1:%.c=%)): $(1) $(call test_archs,$(dir $(1)),$(2)) tests/test_helpers.h | $$(DEPS_STAMP)
	@mkdir -p $$(@D)
	@echo "  TEST    $$@"; $(3) -DFIXTURES_DIR='"$(CURDIR)/fixtures"' -o $$@ $(1) \
	  -Wl,--start-group $(call test_archs,$(dir $(1)),$(2)) -Wl,--end-group $(TEST_LIBS)
endef
$(foreach s,$(UNIT_SRCS),$(eval $(call unit_test,$(s),$(BUILD),$(CC) $(TEST_CFLAGS))))

# c4g-ident's in-process units (C++, CMocka): tests/ident/test_*.cpp link the tool's objects
# but main.o (built with the tool, so only where c4g-ident is built)
IDENT_UNIT_SRCS := $(wildcard tests/ident/test_*.cpp)
IDENT_UNIT_BINS := $(if $(filter c4g-ident,$(TOOLS_BUILT)),$(IDENT_UNIT_SRCS:tests/ident/%.cpp=$(BUILD)/tests/%))
$(BUILD)/tests/test_%: tests/ident/test_%.cpp $(filter-out %/main.o,$(c4g-ident_OBJS)) $(ARCHIVES) tools/c4g-ident/*.hpp \
  | $(DEPS_STAMP)
	@mkdir -p $(@D)
	@echo "  TEST    $@"; $(CXX) $(TOOL_CXXFLAGS) -isystem /usr/include/eigen3 -Itools/c4g-ident $(ARCH_INC) \
	  -DFIXTURES_DIR='"$(CURDIR)/fixtures"' -O2 -g -o $@ $< $(filter-out %/main.o,$(c4g-ident_OBJS)) $(ARCHIVES) \
	  $(c4g-ident_LDLIBS) -lcmocka -lm

unit: $(UNIT_BINS) $(IDENT_UNIT_BINS)
	@sh scripts/run-tests.sh unit $(UNIT_BINS) $(IDENT_UNIT_BINS)

# ---- flavours: $(1) name, $(2) compiler, $(3) flags
ALL_C_TOOL_SRCS := $(foreach t,$(C_TOOLS),$(call tool_srcs,$(t)))
define flavour
$(1)_DIR := $$(BUILD)/$(1)
$$(BUILD)/$(1)/obj/%.o: %.c $$(LIB_HDRS) $$(SIM_HDRS) $$(HOST_HDRS) $$(wildcard tools/*/*.h) | $$(DEPS_STAMP)
	@mkdir -p $$(@D)
	@echo "  $(1)CC  $$@"; $(2) $(3) $$(ARCH_INC) $$(TOOL_INC) -c $$< -o $$@
$$(BUILD)/$(1)/lib/libc4gopen.a: $$(LIB_SRCS:%.c=$$(BUILD)/$(1)/obj/%.o)
	@mkdir -p $$(@D); rm -f $$@; ar rcs $$@ $$^
$$(BUILD)/$(1)/lib/libc4gopen-sim.a: $$(SIM_SRCS:%.c=$$(BUILD)/$(1)/obj/%.o)
	@mkdir -p $$(@D); rm -f $$@; ar rcs $$@ $$^
$$(BUILD)/$(1)/lib/libc4gopen-host.a: $$(HOST_SRCS:%.c=$$(BUILD)/$(1)/obj/%.o)
	@mkdir -p $$(@D); rm -f $$@; ar rcs $$@ $$^
$(1)_ARCH := $$(call TOOL_C_LIBS,$$(BUILD)/$(1)) $$(BUILD)/$(1)/lib/libc4gopen-host.a \
  $$(BUILD)/$(1)/lib/libc4gopen-sim.a $$(BUILD)/$(1)/lib/libc4gopen.a
.SECONDARY: $$(patsubst %.c,$$(BUILD)/$(1)/obj/%.o,$$(LIB_SRCS) $$(SIM_SRCS) $$(HOST_SRCS) $$(ALL_C_TOOL_SRCS))
endef
define flavour_tool
$$(BUILD)/$(1)/tools/lib$(2).a: $$(patsubst %.c,$$(BUILD)/$(1)/obj/%.o,$$(call tool_srcs,$(2)))
	@mkdir -p $$(@D); rm -f $$@; ar rcs $$@ $$^
endef

# ---- ASan + UBSan build of the unit tests
SAN_FLAGS := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
$(eval $(call flavour,san,$(CLANG),$(TEST_CFLAGS) $(SAN_FLAGS)))
$(foreach t,$(C_TOOLS),$(eval $(call flavour_tool,san,$(t))))
$(foreach s,$(UNIT_SRCS),$(eval $(call unit_test,$(s),$(BUILD)/san,$(CLANG) $(TEST_CFLAGS) $(SAN_FLAGS))))
sanitize: $(UNIT_NAMES:%=$(BUILD)/san/tests/%)
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

# ---- coverage of the two pure archives (gcov + lcov): 100% lines, >= 95% branches
COV_LINES ?= 100
COV_BRANCHES ?= 95
COV_FLAGS := $(TEST_CFLAGS) -O0 --coverage -DNDEBUG
$(eval $(call flavour,cov,gcc,$(COV_FLAGS)))
$(foreach t,$(C_TOOLS),$(eval $(call flavour_tool,cov,$(t))))
$(foreach s,$(UNIT_SRCS),$(eval $(call unit_test,$(s),$(BUILD)/cov,gcc $(COV_FLAGS))))
# the counts of every test binary add up in the shared objects' .gcda files: start from zero
coverage: $(UNIT_NAMES:%=$(BUILD)/cov/tests/%)
	@find $(BUILD)/cov -name '*.gcda' -delete; rm -f $(BUILD)/cov/*.info
	@cd $(BUILD)/cov/tests && for t in $(UNIT_NAMES); do ./$$t >/dev/null 2>&1 || { echo "coverage: $$t failed"; exit 1; }; done
	@sh scripts/coverage-gate.sh $(BUILD)/cov $(COV_LINES) $(COV_BRANCHES) $(PURE_SRCS)

# ---- fuzzing (libFuzzer via clang), bounded: every target links the fuzz flavour's archives
FUZZ_SAN := -g -O1 -fsanitize=address,undefined -fno-sanitize-recover=all
FUZZ_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE $(FUZZ_SAN)
$(eval $(call flavour,fuzz,$(CLANG),$(FUZZ_CFLAGS) -fsanitize=fuzzer-no-link))
$(foreach t,$(C_TOOLS),$(eval $(call flavour_tool,fuzz,$(t))))
$(BUILD)/fuzz/fuzz_%: tests/fuzz/fuzz_%.c $(fuzz_ARCH) $(wildcard tests/fuzz/*.h) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	@echo "  FUZZLD  $@"; $(CLANG) $(FUZZ_CFLAGS) $(ARCH_INC) $(TOOL_INC) -fsanitize=fuzzer -o $@ $< \
	  -Wl,--start-group $(fuzz_ARCH) -Wl,--end-group $(TOOL_LIB_LIBS)

# the differential test's reference and drive are headers of tests/lib (every flavour)
REF_HDRS := tests/lib/ref_safety.h tests/lib/ref_drive.h
$(BUILD)/tests/test_ref_safety $(BUILD)/san/tests/test_ref_safety $(BUILD)/cov/tests/test_ref_safety \
  $(BUILD)/fuzz/fuzz_safety_ref: $(REF_HDRS)
fuzz-build: $(FUZZ_NAMES:%=$(BUILD)/fuzz/%)
# one target per run, so `make -jN fuzz` runs N fuzzers at a time
fuzz: $(FUZZ_NAMES:%=fuzz-run-%)
fuzz-run-%: $(BUILD)/fuzz/%
	@sh scripts/run-fuzz.sh $(BUILD)/fuzz $(FUZZ_SECONDS) $*

# ---- symbol audit, cross builds, qemu smoke test
# each archive exports exactly what its headers declare, under its own prefix; the pure two
# hold no mutable state and need nothing from outside but the C library's mem* functions
audit: $(STATIC) $(SIM_LIB) $(HOST_LIB)
	@sh scripts/check-symbols.sh nm $(STATIC) c4g_ pure include/*.h
	@sh scripts/check-symbols.sh nm $(SIM_LIB) c4gsim_ pure lib/sim/*.h
	@sh scripts/check-symbols.sh nm $(HOST_LIB) c4gh_ host lib/host/*.h
	@if grep -rnE '(\.|->)priv\.' tools lib/host lib/sim examples bench --include='*.c' --include='*.cpp' --include='*.h'; then \
	  echo "audit: the lines above reach a library struct's priv member: use the accessors" >&2; exit 1; \
	 else echo "audit: no tool, host or example code reaches a library struct's priv member"; fi

ARM_FLAGS := -std=c99 -pedantic-errors $(WARN_LIB) -Iinclude -Ilib/sim -Os -ffreestanding
cross: | $(DEPS_STAMP)
	@rm -rf $(BUILD)/arm $(BUILD)/armbe && mkdir -p $(BUILD)/arm $(BUILD)/armbe
	@set -e; for f in $(PURE_SRCS); do \
	  $(ARM_CC) $(ARM_FLAGS) -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -c $$f -o $(BUILD)/arm/$$(basename $$f .c).o; \
	  $(ARM_CC) $(ARM_FLAGS) -mcpu=cortex-r5 -marm -mbig-endian -c $$f -o $(BUILD)/armbe/$$(basename $$f .c).o; done
	@for d in arm armbe; do \
	  arm-none-eabi-ld -r $$(test $$d = armbe && echo -EB) -o $(BUILD)/$$d/all.o $(addprefix $(BUILD)/$$d/,$(notdir $(LIB_SRCS:.c=.o))) && \
	  arm-none-eabi-objcopy --localize-hidden $(BUILD)/$$d/all.o && \
	  arm-none-eabi-ar rcs $(BUILD)/$$d/libc4gopen.a $(BUILD)/$$d/all.o && \
	  sh scripts/check-symbols.sh arm-none-eabi-nm $(BUILD)/$$d/libc4gopen.a c4g_ pure include/*.h && \
	  $(if $(filter lib/sim/%,$(PURE_SRCS)),arm-none-eabi-ar rcs $(BUILD)/$$d/libc4gopen-sim.a $(addprefix $(BUILD)/$$d/,$(notdir $(SIM_SRCS:.c=.o))) && \
	  sh scripts/check-symbols.sh arm-none-eabi-nm $(BUILD)/$$d/libc4gopen-sim.a c4gsim_ pure lib/sim/*.h &&) true || exit 1; done
	@echo "cross: cortex-m4 thumb size:"; arm-none-eabi-size -t $(BUILD)/arm/libc4gopen.a | tail -1
	@echo "cross: cortex-r5 big-endian OK"

qemu-smoke: | $(DEPS_STAMP)
	@mkdir -p $(BUILD)/qemu
	$(ARM_CC) -std=c99 -O1 -Iinclude -marm -mcpu=arm926ej-s --specs=rdimon.specs \
	  -DFIXTURE_INIT='"$(CURDIR)/fixtures/vectors/init-fig10-1.bin"' \
	  -Ilib/sim tests/target/target_smoke.c $(LIB_SRCS) $(SIM_SRCS) -o $(BUILD)/qemu/target_smoke.elf -lm
	qemu-arm $(BUILD)/qemu/target_smoke.elf
	$(ARM_CC) -std=c99 -O2 -Iinclude -marm -mcpu=cortex-r5 -mfpu=vfpv3-d16 -mfloat-abi=hard -mbig-endian -mbe8 -ffreestanding -nostdlib \
	  -static -Wl,--be8 tests/target/target_be_codec.c lib/wire/c4g_codec.c lib/wire/c4g_modes.c \
	  lib/wire/c4g_init.c -o $(BUILD)/qemu/target_be_codec.elf
	qemu-armeb $(BUILD)/qemu/target_be_codec.elf && echo "qemu-smoke: big-endian codec and init packet OK (qemu-armeb)"

# ---- static analysis
cppcheck: | $(DEPS_STAMP)
	@mkdir -p $(BUILD)
	cppcheck --quiet --std=c99 --language=c --enable=warning,style,performance,portability \
	  --inline-suppr --error-exitcode=2 --suppress=missingIncludeSystem -Iinclude -Ilib/sim $(PURE_SRCS)
	@echo "cppcheck: clean"
misra: | $(DEPS_STAMP)
	@mkdir -p $(BUILD)
	@rm -f $(BUILD)/misra.txt
	@mkdir -p $(BUILD)/cppcheck-misra
	cppcheck --quiet --std=c99 --language=c --addon=misra --inline-suppr \
	  --cppcheck-build-dir=$(BUILD)/cppcheck-misra \
	  --suppressions-list=scripts/cppcheck-misra.supp -Iinclude --error-exitcode=3 \
	  --output-file=$(BUILD)/misra.txt -Ilib/sim $(PURE_SRCS)
	@if [ -s $(BUILD)/misra.txt ]; then cat $(BUILD)/misra.txt; echo "misra: findings above (see docs/misra-deviations.md)"; exit 1; fi
	@echo "misra: clean (deviations: docs/misra-deviations.md)"
clang-tidy: | $(DEPS_STAMP)
	clang-tidy --quiet $(PURE_SRCS) -- -std=c99 -Iinclude -Ilib/sim
	@echo "clang-tidy: clean"
analyzer: | $(DEPS_STAMP)
	@mkdir -p $(BUILD)/fanalyzer
	@set -e; for f in $(PURE_SRCS); do gcc -std=c99 -fanalyzer -Werror -Iinclude -Ilib/sim -c $$f -o $(BUILD)/fanalyzer/$$(basename $$f .c).o; done
	@echo "analyzer: gcc -fanalyzer clean"
# Cognitive complexity of the tools and tests (laxer than the library's 25, set in
# .clang-tidy): functions of one job each, mains that only wire the parts together.
TOOL_COMPLEXITY ?= 40
TEST_COMPLEXITY ?= 90
CPLX_INC := -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -DFIXTURES_DIR=\"\" -Itests $(ARCH_INC) $(TOOL_INC)
complexity: | $(DEPS_STAMP)
	@sh scripts/complexity.sh $(TOOL_COMPLEXITY) "$(CPLX_INC)" $(sort $(wildcard tools/*/*.c)) $(HOST_SRCS)
	@sh scripts/complexity.sh $(TEST_COMPLEXITY) "$(CPLX_INC)" $(UNIT_SRCS) $(FUZZ_SRCS)
# Statuses nobody reads: clang honours C4G_NODISCARD (and a deliberate (void) cast).
nodiscard: | $(DEPS_STAMP)
	@set -e; for f in $(sort $(wildcard tools/*/*.c)) $(HOST_SRCS) examples/*.c docs/examples/*.c bench/*.c $(UNIT_SRCS) $(FUZZ_SRCS); do \
	  $(CLANG) $(CPLX_INC) -fsyntax-only -Werror=unused-result $$f; done
	@echo "nodiscard: every status is used or deliberately dropped"
static-analysis: cppcheck misra clang-tidy analyzer complexity nodiscard

# ---- end-to-end tests (real processes, loopback) and doc examples
# ---- e2e: the harness (tests/e2e, pytest) and its C helpers
# Every tests/e2e/helpers/*.c is built against the three archives into $(BUILD)/e2e (each
# links only the members it uses; -lpcap for the capture helpers).
E2E_HELPER_SRCS := $(sort $(wildcard tests/e2e/helpers/*.c))
E2E_HELPERS := $(E2E_HELPER_SRCS:tests/e2e/helpers/%.c=$(BUILD)/e2e/%)
E2E_HELPER_CFLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -Wall -Wextra \
  -Werror $(ARCH_INC)
.PHONY: e2e-helpers
e2e-helpers: $(E2E_HELPERS)
# A helper that needs more names it: E2E_EXTRA_<name> (flags and archives before the
# library's), E2E_LIBS_<name> (system libraries after it), and a prerequisite line.
$(BUILD)/e2e/%: tests/e2e/helpers/%.c $(ARCHIVES) | $(DEPS_STAMP)
	@mkdir -p $(@D)
	@echo "  CC      $@"; $(CC) $(E2E_HELPER_CFLAGS) -o $@ $< $(E2E_EXTRA_$*) $(ARCHIVES) $(E2E_LIBS_$*) -lpcap -lm
# arm_exact (the arm plant's exact rigid parameters) opens the plant through c4g-sim's
# archive and MuJoCo.
E2E_EXTRA_arm_exact = -Itools/c4g-sim $(BUILD)/tools/libc4g-sim.a
E2E_LIBS_arm_exact = $(TOOL_LIB_LIBS)
$(BUILD)/e2e/arm_exact: $(BUILD)/tools/libc4g-sim.a
e2e: all e2e-helpers
	@sh scripts/run-e2e.sh $(BUILD)

# ---- c4g-ident's accuracy against c4g-sim's axis model, in-process (tests/ident)
IDENT_ACC := $(BUILD)/tests/ident-accuracy
IDENT_SEEDS ?= 6
# c4g-ident's own objects (built for the tool), the harness compiled beside them
IDENT_TOOL_OBJS := $(addprefix $(BUILD)/tobj/tools/c4g-ident/,signal.o fit.o excite.o)
IDENT_OBJS := $(BUILD)/tests/ident-obj/accuracy.o $(BUILD)/tests/ident-obj/simgen.o \
  $(BUILD)/tests/ident-obj/model.o
$(BUILD)/tests/ident-obj/%.o: tests/ident/%.cpp tests/ident/simgen.hpp tools/c4g-ident/ident.hpp \
  tools/c4g-ident/excite.hpp lib/sim/c4gsim_model.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(CXX) $(TOOL_CXXFLAGS) -isystem /usr/include/eigen3 -Itools/c4g-ident $(ARCH_INC) -O2 -g -c $< -o $@
$(BUILD)/tests/ident-obj/model.o: lib/sim/c4gsim_model.c lib/sim/c4gsim_model.h | $(DEPS_STAMP)
	@mkdir -p $(@D)
	$(CC) $(TOOL_CFLAGS) $(ARCH_INC) -O2 -c $< -o $@
$(IDENT_ACC): $(IDENT_OBJS) $(IDENT_TOOL_OBJS)
	$(CXX) -o $@ $^ -lceres -lglog -lpthread -lm
ident-accuracy: $(IDENT_ACC)
	@echo "== c4g-ident accuracy ($(IDENT_SEEDS) seeds per case; make bench runs 30)"
	@$(IDENT_ACC) --seeds $(IDENT_SEEDS) --gate
docs-examples: $(STATIC)
	@sh scripts/docs-examples.sh $(BUILD)
# every command block of README.md and docs/*.md, as written (part of the e2e gate)
docs-commands: all e2e-helpers
	@E2E_ONLY=docs_commands sh scripts/run-e2e.sh $(BUILD)

# ---- the two README commands
# The gates after "--" only compute: they run at nice 19 beside the others, mostly while the
# e2e gate waits on real-time sessions (scripts/check.sh says how).
CHECK_GATES := all unit ident-accuracy sanitize valgrind coverage e2e \
  -- audit cross qemu-smoke docs-examples static-analysis fuzz
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
# The dynamic linker finds a new shared library only after ldconfig: run it when root installs
# into a default prefix of the system (not into a DESTDIR: a package's own scripts run it
# there); for any other prefix install prints the two variables a program needs.
LDCONFIG ?= ldconfig
RUN_LDCONFIG = $(if $(DESTDIR),,$(if $(filter /usr/local /usr,$(PREFIX)),$(if $(filter 0,$(shell id -u)),yes)))
# The pages and their pictures go to DOC_DIR, the fixtures they run on to DATA_DIR. The pages
# name fixtures/ and build/bin/ as in the source tree (where tests/e2e/test_docs_commands.py
# runs them); installed, they name the installed copies, and README.md its neighbours (the
# fuzz corpus stays a source-tree folder).
DOC_DIR = $(PREFIX)/share/doc/libc4gopen
DATA_DIR = $(PREFIX)/share/c4gopen
DOC_FIXTURES = $(shell find fixtures -path fixtures/fuzz -prune -o -type f -print 2>/dev/null | LC_ALL=C sort)
DOC_SED = -e 's,\(^\|[^A-Za-z0-9_./-]\)fixtures/,\1$(DATA_DIR)/fixtures/,g' \
  -e 's,\(^\|[^A-Za-z0-9_./-]\)build/bin/,\1$(PREFIX)/bin/,g' -e 's,](docs/,](,g' \
  -e 's,$(DATA_DIR)/fixtures/fuzz/,fixtures/fuzz/,g'
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
	install -m 644 LICENSE $(DESTDIR)$(PREFIX)/share/doc/libc4gopen/
	@for f in docs/*.md README.md; do echo "  DOC     $(DOC_DIR)/$${f##*/}"; \
	  sed $(DOC_SED) $$f > $(DESTDIR)$(DOC_DIR)/$${f##*/} || exit 1; done
	install -d $(DESTDIR)$(DOC_DIR)/img
	install -m 644 docs/img/* $(DESTDIR)$(DOC_DIR)/img/
	@set -e; for f in $(DOC_FIXTURES); do install -D -m 644 $$f $(DESTDIR)$(DATA_DIR)/$$f; done; \
	  echo "  DATA    $(DATA_DIR)/fixtures ($(words $(DOC_FIXTURES)) files)"
	install -d $(DESTDIR)$(PREFIX)/share/doc/libc4gopen/examples
	install -m 644 examples/mode4_loop.c examples/README.md $(DESTDIR)$(PREFIX)/share/doc/libc4gopen/examples/
	sed 's|/usr/local/bin/|$(PREFIX)/bin/|' examples/c4g-server.service \
	  > $(DESTDIR)$(PREFIX)/share/doc/libc4gopen/examples/c4g-server.service
	install -d $(DESTDIR)$(PREFIX)/share/man/man1 $(DESTDIR)$(PREFIX)/share/man/man3
	$(if $(filter %.1,$(MAN_PAGES)),install -m 644 $(filter %.1,$(MAN_PAGES)) $(DESTDIR)$(PREFIX)/share/man/man1/)
	$(if $(filter %.3,$(MAN_PAGES)),install -m 644 $(filter %.3,$(MAN_PAGES)) $(DESTDIR)$(PREFIX)/share/man/man3/)
	$(if $(MAN_HDR_PAGES),install -m 644 $(BUILD)/man/fn/*.3 $(DESTDIR)$(PREFIX)/share/man/man3/)
	install -d $(DESTDIR)$(BASH_COMPLETION_DIR)
	install -m 644 scripts/completion/c4gopen.bash $(DESTDIR)$(BASH_COMPLETION_DIR)/c4g-server
	$(foreach t,$(filter-out c4g-server,$(TOOL_NAMES)),ln -sf c4g-server $(DESTDIR)$(BASH_COMPLETION_DIR)/$(t);)
	install -d $(DESTDIR)$(WIRESHARK_PLUGIN_DIR)
	install -m 644 tools/wireshark/c4gopen.lua $(DESTDIR)$(WIRESHARK_PLUGIN_DIR)/
	$(if $(DESTDIR),@:,$(if $(RUN_LDCONFIG),$(LDCONFIG),@echo "install: programs find libc4gopen in \
	  $(PREFIX)/lib with: export PKG_CONFIG_PATH=$(PREFIX)/lib/pkgconfig LD_LIBRARY_PATH=$(PREFIX)/lib"))
uninstall:
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/include/,$(notdir $(wildcard include/*.h)))
	rm -f $(DESTDIR)$(PREFIX)/lib/libc4gopen.a $(DESTDIR)$(PREFIX)/lib/libc4gopen.so*
	rm -f $(DESTDIR)$(PREFIX)/lib/pkgconfig/c4gopen.pc
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/bin/,$(TOOL_NAMES))
	rm -rf $(DESTDIR)$(PREFIX)/share/doc/libc4gopen $(DESTDIR)$(DATA_DIR)
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/share/man/man1/,$(notdir $(filter %.1,$(MAN_ALL))))
	rm -f $(addprefix $(DESTDIR)$(PREFIX)/share/man/man3/,$(notdir $(filter %.3,$(MAN_ALL))))
	@for f in $(DESTDIR)$(PREFIX)/share/man/man3/c4g_*.3; do \
	  if [ -f "$$f" ] && grep -q '^\.so man3/c4gopen_' "$$f"; then rm -f "$$f"; fi; done
	rm -f $(addprefix $(DESTDIR)$(BASH_COMPLETION_DIR)/,$(TOOL_NAMES))
	rm -f $(DESTDIR)$(WIRESHARK_PLUGIN_DIR)/c4gopen.lua
wireshark-install-user:
	install -d $(WIRESHARK_USER_PLUGIN_DIR)
	install -m 644 tools/wireshark/c4gopen.lua $(WIRESHARK_USER_PLUGIN_DIR)/

clean:
	rm -rf $(BUILD)
