"""Log analysis for navcli: reads MCAP logs into pandas; never imports the simulator."""

from .logs import LogError, RunLog, path_length, read_log

__all__ = ["LogError", "RunLog", "path_length", "read_log"]
