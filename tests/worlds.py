"""The small worlds the slower tests run on, each defined once: a test file's config is one of them plus what it
changes (its episodes, seed or switch states)."""

#: a 6 x 6 world with 5 unsafe cells and fits on 80 rows: a few episodes of a paired run in seconds (the live run,
#: the dashboards, the audit, the third model)
SIX_BY_SIX = dict(grid_size=6, n_unsafe=5, offline_episodes=8, cost_fit_points=80, reward_fit_points=80,
                  optimizer_steps=5, k_prior=30)
#: a 5 x 5 world with 3 unsafe cells and the least data: the sweeps and the commands that run many cells
FIVE_BY_FIVE = dict(grid_size=5, n_unsafe=3, offline_episodes=5, cost_fit_points=50, reward_fit_points=50,
                    k_prior=20, optimizer_steps=3)
#: the same 5 x 5 world with a little more data (6 offline episodes, fits on 60 rows): the ablation's settings, one
#: experiment followed step by step
FIVE_BY_FIVE_MORE_DATA = dict(FIVE_BY_FIVE, offline_episodes=6, cost_fit_points=60, reward_fit_points=60)
