cell-cli_LDLIBS := -ledit -linih -ljansson
