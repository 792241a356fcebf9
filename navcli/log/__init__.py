"""The log: navcli's one file format, and everything that writes it.

- :mod:`~navcli.log.format`: the topic names and the JSON messages (msgspec structs) with their
  schemas; imports only msgspec, so :mod:`navcli.analysis` can read by it without the simulator;
- :mod:`~navcli.log.writer`: the recorder, the only writer of logs;
- :mod:`~navcli.log.compression`: how its chunks may be compressed, and the default;
- :mod:`~navcli.log.scenes`: what the 3D panel draws;
- :mod:`~navcli.log.recover`: a killed run's ``.partial`` made into a valid log;
- :mod:`~navcli.log.layout`: the Foxglove layout that shows a log.
"""
