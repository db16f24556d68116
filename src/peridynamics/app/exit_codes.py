"""Exit codes of the ``peridynamics`` commands (the command line and the application
commands it starts share them)."""

EXIT_OK = 0
#: an invalid deck or set-up, a model too large for this machine, bad arguments
EXIT_INVALID = 2
#: the run went unstable (summary.json and last_good.vtu are written)
EXIT_UNSTABLE = 3
#: ``peridynamics sweep``: some case failed or went unstable (the others ran)
EXIT_CASES_FAILED = 4
#: interrupted by Ctrl-C (or SIGTERM in a sweep)
EXIT_INTERRUPTED = 130
