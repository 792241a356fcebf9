"""The Learning Agent's training harness (learning-agent paper, section 6), apart from the agent
itself (:mod:`navcli.learning`): :mod:`.task` (trials from random starts, action by action, under
the paper's conditions), :mod:`.trainer` (``navcli train``: trials, evaluations, the learning
curve, resumable) and :mod:`.comparison` (``navcli compare policies``: the paper's Table 1).
"""
