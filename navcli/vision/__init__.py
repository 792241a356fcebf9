"""The Vision system (notes, section 1): the camera on its pan unit (:mod:`.camera`), the visual
memory of fuzzy positions (:mod:`.visual_memory`), and the perceptions that turn them, or ground
truth, into the agents' beliefs (:mod:`.perception`)."""
