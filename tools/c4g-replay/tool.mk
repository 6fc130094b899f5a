# rerun drives c4g-server's per-datagram core over a capture: it links c4g-server's archive.
c4g-replay_USES := c4g-server
c4g-replay_CPPFLAGS := -Itools/c4g-server
c4g-replay_LDLIBS := -lpcap -ljansson -linih -lpthread
