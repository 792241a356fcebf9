"""navcli: a mission runner for the bidding Pilot/Vision/Navigation robot of Busquets, Mohan et al."""

__version__ = "0.1.0"
