// Linked into the executables of sanitized builds only (POLARCAM_SANITIZE). LeakSanitizer reports the memory that
// fontconfig and libltdl (loaded by PLplot's cairo driver) keep until exit; those are not polarcam's leaks, and
// without this every command or test that draws a figure would fail a sanitized run.
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig.so\nleak:libltdl.so\n"; }

// Without this LeakSanitizer prints a table of the suppressions it used on stderr at exit, which would break the
// one-line error contract that the tests check.
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }
