"""Exit codes of the ``peridynamics`` commands (the command line and the application
commands it starts share them)."""

EXIT_OK = 0
#: an invalid deck or set-up, a model too large for this machine, bad arguments
EXIT_INVALID = 2
#: the run went unstable (summary.json and last_good.vtu are written)
EXIT_UNSTABLE = 3
#: ``peridynamics sweep``: some case failed or went unstable (the others ran)
EXIT_CASES_FAILED = 4
#: interrupted by Ctrl-C (SIGINT); another stop signal gives 128 + its number
#: (:func:`exit_for_signal`: SIGHUP 129, SIGUSR1 138, SIGTERM 143), as a shell reports a
#: process killed by it
EXIT_INTERRUPTED = 130


def exit_for_signal(signum: int) -> int:
    """The exit code of a run stopped by signal ``signum``: 128 + ``signum``."""
    return 128 + int(signum)
