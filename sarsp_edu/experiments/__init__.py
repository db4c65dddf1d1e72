"""Runs and what is computed from them: one run or a paired comparison (``experiment``), the paper's metrics and
Definition 4 (``metrics``), stored results (``results``), the 45-configuration grid (``sweep``), Tables 1-4
(``tables``), the comparison under other settings (``ablation``), the three models against the variance
threshold (``thresholds``), each model's safe set held to the world (``audit``), runs whose cost and reward models
are of different kinds and the reward model's ranking along a run (``ranking``) and which code computed a result
(``provenance``)."""
