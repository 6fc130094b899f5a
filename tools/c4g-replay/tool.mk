# c4g-replay links libpcap (captures), jansson (--json) and inih (c4gh_textfile, which the
# option parsing pulls in).
c4g-replay_LDLIBS := -lpcap -ljansson -linih
