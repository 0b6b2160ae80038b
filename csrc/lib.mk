# libtendonrod: the C core (csrc/*.c) built on its own, without Python, as a shared and a
# static library, with its public headers (tendonrod.h, tr_batch.h) and a pkg-config file.
# Included by the top-level Makefile; paths are relative to the repository root.
#   make libtendonrod               build/c/libtendonrod.so.<version>, .so, .a
#   make install-c PREFIX=/opt/tr   lib/, include/tendonrod/, lib/pkgconfig/tendonrod.pc
#   make c-example                  install into build/c/prefix, then build and run
#                                   examples/c against the installed library (CI)
PREFIX   ?= /usr/local
CC       ?= cc
CBUILD   := build/c
# the C library's version, from tendonrod.h (TR_VERSION_MAJOR, _MINOR, _PATCH)
TR_VERSION = $(shell sed -n 's/^\#define TR_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\)$$/\2/p' csrc/tendonrod.h | paste -sd.)
# 0.x: no ABI promise between minor versions, so the soname carries major.minor
TR_SOVER   = $(word 1,$(subst ., ,$(TR_VERSION))).$(word 2,$(subst ., ,$(TR_VERSION)))
SONAME     = libtendonrod.so.$(TR_SOVER)
# the core's flags (csrc/CFLAGS, as setup.py reads them) and GSL's from pkg-config
TR_CFLAGS  = $(shell grep -v '^\#' csrc/CFLAGS) -fPIC
GSL_CFLAGS = $(shell pkg-config --cflags gsl)
GSL_LIBS   = $(shell pkg-config --libs gsl)
LIB_SRC   := $(wildcard csrc/*.c)
LIB_OBJ   := $(patsubst csrc/%.c,$(CBUILD)/obj/%.o,$(LIB_SRC))
LIB_HDR   := csrc/tendonrod.h csrc/tr_batch.h

.PHONY: libtendonrod install-c c-example

$(CBUILD)/obj/%.o: csrc/%.c $(wildcard csrc/*.h) csrc/CFLAGS | gsl
	@mkdir -p $(@D)
	$(CC) $(TR_CFLAGS) $(GSL_CFLAGS) -Icsrc -c $< -o $@

# exports: the tr_-prefixed names only (csrc/libtendonrod.map)
$(CBUILD)/libtendonrod.so.$(TR_VERSION): $(LIB_OBJ) csrc/libtendonrod.map
	$(CC) -shared -Wl,-soname,$(SONAME) -Wl,--version-script=csrc/libtendonrod.map \
	  -o $@ $(LIB_OBJ) $(GSL_LIBS) -lm

$(CBUILD)/libtendonrod.a: $(LIB_OBJ)
	rm -f $@ && ar rcs $@ $^

libtendonrod: $(CBUILD)/libtendonrod.so.$(TR_VERSION) $(CBUILD)/libtendonrod.a
	ln -sf libtendonrod.so.$(TR_VERSION) $(CBUILD)/$(SONAME)
	ln -sf $(SONAME) $(CBUILD)/libtendonrod.so

install-c: libtendonrod
	install -d $(DESTDIR)$(PREFIX)/lib/pkgconfig $(DESTDIR)$(PREFIX)/include/tendonrod
	install -m 644 $(LIB_HDR) $(DESTDIR)$(PREFIX)/include/tendonrod/
	install -m 755 $(CBUILD)/libtendonrod.so.$(TR_VERSION) $(DESTDIR)$(PREFIX)/lib/
	ln -sf libtendonrod.so.$(TR_VERSION) $(DESTDIR)$(PREFIX)/lib/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(PREFIX)/lib/libtendonrod.so
	install -m 644 $(CBUILD)/libtendonrod.a $(DESTDIR)$(PREFIX)/lib/
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(TR_VERSION)|' csrc/tendonrod.pc.in \
	  > $(DESTDIR)$(PREFIX)/lib/pkgconfig/tendonrod.pc

# the example built by its own Makefile against the installed copy (pkg-config only: no
# path into this tree), shared and static, and run
c-example:
	rm -rf $(CBUILD)/prefix $(CBUILD)/example
	$(MAKE) --no-print-directory install-c PREFIX=$(abspath $(CBUILD)/prefix)
	cp -r examples/c $(CBUILD)/example
	PKG_CONFIG_PATH=$(abspath $(CBUILD)/prefix)/lib/pkgconfig $(MAKE) --no-print-directory -C $(CBUILD)/example run
