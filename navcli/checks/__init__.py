"""What a caller gives and what a command needs, checked before any work: the Python API's
arguments (:mod:`~navcli.checks.arguments`) and the optional extras a command imports
(:mod:`~navcli.checks.extras`). Standard library only."""
