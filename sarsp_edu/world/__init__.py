"""The world and its data: the safe gridworld, a Gymnasium environment, and its covariate shift (``gridworld``);
the models' inputs, offline data and injected outliers (``offline``); what a run needs before its agent
(``preparation``: world, data, outliers, shift, seeds)."""
