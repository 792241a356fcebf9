"""The experiment runners: ``navcli compare`` (:mod:`.compare`) and ``navcli bench`` (:mod:`.bench`).
They plan and run lists of :class:`~navcli.config.RunSpec`; the tables come from the logs, in
``analysis``."""
