"""navcli's learners beyond the learning paper, each beside the paper's rows (never in place of
them): the temperature of the ``softmax`` policy chosen on training rooms (:mod:`.temperature`,
``navcli tune-softmax``) and a Stable-Baselines3 agent trained through the Gymnasium environment
(:mod:`.sb3`, ``navcli train-rl``; the optional extra ``navcli[rl]``). The policies they make are
:mod:`navcli.learning.softmax` and :mod:`navcli.learning.ppo`.
"""
