from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from sarsp_edu import DOWN, LEFT, RIGHT, UP, SafeGridWorld, cost_inputs, reward_inputs
from sarsp_edu.world.gridworld import MOVES, OBSERVATION_FIELDS


def touching(a, b):
    return abs(a[0] - b[0]) + abs(a[1] - b[1]) <= 1


def assert_spaced(cells):
    cells = [tuple(c) for c in cells]
    for i in range(len(cells)):
        for j in range(i + 1, len(cells)):
            assert not touching(cells[i], cells[j]), f"{cells[i]} and {cells[j]} touch"


@pytest.mark.parametrize("render_mode", ["ansi", "rgb_array"])
def test_gymnasium_check_env(render_mode):
    # made through gymnasium so that it has a spec and every render mode is checked
    check_env(gym.make("sarsp_edu/SafeGridWorld-v0", seed=0, render_mode=render_mode).unwrapped)


def test_registered_with_gymnasium():
    env = gym.make("sarsp_edu/SafeGridWorld-v0", size=6, n_unsafe=4, seed=0)
    observation, _ = env.reset(seed=0)
    assert observation.shape == (8,)
    assert env.unwrapped.size == 6


def test_defaults_are_the_papers():
    env = SafeGridWorld()
    assert (env.size, env.n_unsafe, env.d, env.max_steps) == (10, 15, 1.0, 100)
    assert (RIGHT, DOWN, LEFT, UP) == (0, 1, 2, 3)
    np.testing.assert_array_equal(MOVES, [[1, 0], [0, 1], [-1, 0], [0, -1]])


@pytest.mark.parametrize("seed", range(20))
def test_unsafe_states_are_spaced_and_avoid_start_and_goal(seed):
    env = SafeGridWorld(seed=seed)
    unsafe = env.unsafe_states
    assert unsafe.shape == (15, 2)
    assert len({tuple(c) for c in unsafe}) == 15
    assert_spaced(unsafe)
    assert env.start not in map(tuple, unsafe) and env.goal not in map(tuple, unsafe)
    for _ in range(10):
        env.reset()
        assert env.start != env.goal
        cells = set(map(tuple, unsafe))
        assert env.start not in cells and env.goal not in cells
        np.testing.assert_array_equal(env.unsafe_states, unsafe)  # a reset keeps them


def test_placement_reference_never_uses_the_last_row_or_column():
    for seed in range(20):
        env = SafeGridWorld(seed=seed, placement="reference")
        env.reset()
        assert env.unsafe_states.max() <= 8
        assert max(env.start + env.goal) <= 8
        env.shift(10, rng=seed)
        assert env.unsafe_states.max() <= 8


def test_placement_full_uses_the_whole_grid():
    seen = np.concatenate([SafeGridWorld(seed=s).unsafe_states for s in range(30)])
    assert seen.max() == 9 and seen.min() == 0


def test_moves_and_clipping():
    env = SafeGridWorld(size=5, n_unsafe=1, seed=0)
    # put the single unsafe state out of the way and start in the corner (0, 0)
    env._unsafe = np.array([[4, 4]])
    env.reset(options={"start": (0, 0), "goal": (3, 3)})
    env.step(LEFT)
    assert env.agent_position == (0, 0)  # clipped
    env.step(UP)
    assert env.agent_position == (0, 0)  # clipped
    env.step(RIGHT)
    assert env.agent_position == (1, 0)
    env.step(DOWN)
    assert env.agent_position == (1, 1)
    env.step(LEFT)
    assert env.agent_position == (0, 1)
    env.step(UP)
    assert env.agent_position == (0, 0)


def test_reward_cost_signal_and_violation():
    env = SafeGridWorld(size=6, n_unsafe=2, seed=0)
    env._unsafe = np.array([[2, 0], [5, 5]])
    observation, info = env.reset(options={"start": (0, 0), "goal": (0, 4)})
    assert info["distance_to_unsafe"] == pytest.approx(2.0)
    observation, reward, terminated, truncated, info = env.step(RIGHT)  # to (1, 0)
    assert reward == pytest.approx(-math.hypot(1, 4))  # minus the L2 distance to the goal
    assert info["distance_to_unsafe"] == pytest.approx(1.0)
    assert info["cost"] == 0  # distance 1 is not below d = 1
    observation, reward, terminated, truncated, info = env.step(RIGHT)  # into (2, 0)
    assert info["distance_to_unsafe"] == 0.0 and info["cost"] == 1
    assert not terminated  # unsafe states are not terminal
    assert dict(zip(OBSERVATION_FIELDS, observation)) == {
        "agent_x": 2, "agent_y": 0, "goal_x": 0, "goal_y": 4, "goal_l1_distance": 6,
        "unsafe_x": 2, "unsafe_y": 0, "unsafe_distance": 0.0,
    }


def test_threshold_d_sets_the_violation():
    env = SafeGridWorld(size=6, n_unsafe=1, d=1.5, seed=0)
    env._unsafe = np.array([[2, 0]])
    env.reset(options={"start": (0, 0), "goal": (0, 4)})
    _, _, _, _, info = env.step(RIGHT)  # distance 1 < 1.5
    assert info["cost"] == 1


def test_termination_at_the_goal_and_truncation():
    env = SafeGridWorld(size=6, n_unsafe=1, seed=0)
    env._unsafe = np.array([[5, 5]])
    env.reset(options={"start": (0, 0), "goal": (1, 0)})
    _, reward, terminated, truncated, info = env.step(RIGHT)
    assert terminated and not truncated and info["task_completed"] and reward == 0.0
    with pytest.raises(RuntimeError, match="call reset"):
        env.step(RIGHT)

    short = SafeGridWorld(size=6, n_unsafe=1, max_steps=3, seed=0)
    short._unsafe = np.array([[5, 5]])
    short.reset(options={"start": (0, 0), "goal": (4, 4)})
    flags = [short.step(LEFT)[2:4] for _ in range(3)]
    assert flags == [(False, False), (False, False), (False, True)]
    assert SafeGridWorld(size=7, n_unsafe=5).max_steps == 49  # T_max = n * n


def test_same_seed_same_world_and_episodes():
    def trace(seed):
        env = SafeGridWorld(seed=seed)
        out = [env.unsafe_states.tolist()]
        for _ in range(5):
            observation, _ = env.reset()
            out.append(observation.tolist())
        return out

    assert trace(4) == trace(4)
    assert trace(4) != trace(5)
    a = SafeGridWorld(seed=1)
    np.testing.assert_array_equal(a.reset(seed=9)[0], a.reset(seed=9)[0])


@pytest.mark.parametrize("nss", [0, 2, 6, 10, 15])
def test_shift_moves_exactly_nss_states(nss):
    env = SafeGridWorld(seed=11)
    env.reset(seed=0)
    before = env.unsafe_states
    moved = env.shift(nss, rng=3)
    after = env.unsafe_states
    assert len(moved) == nss and len(set(moved.tolist())) == nss
    stay = np.setdiff1d(np.arange(15), moved)
    np.testing.assert_array_equal(after[stay], before[stay])
    old_cells = set(map(tuple, before[moved]))
    for i in moved:
        assert tuple(after[i]) not in old_cells  # a moved state really moved
    assert_spaced(after)
    assert env.start not in map(tuple, after) and env.goal not in map(tuple, after)
    assert env.agent_position not in map(tuple, after)
    layout = env.layout()
    np.testing.assert_array_equal(layout.moved, moved)
    np.testing.assert_array_equal(layout.moved_from, before[moved])


def test_shift_is_reproducible_from_its_rng():
    a, b = SafeGridWorld(seed=2), SafeGridWorld(seed=2)
    a.shift(8, rng=5)
    b.shift(8, rng=5)
    np.testing.assert_array_equal(a.unsafe_states, b.unsafe_states)


def test_model_inputs():
    observation = np.array([3, 4, 7, 8, 8, 5, 4, 2.0])
    np.testing.assert_array_equal(
        cost_inputs(observation),
        [[0, 3, 4, 5, 4], [1, 3, 4, 5, 4], [2, 3, 4, 5, 4], [3, 3, 4, 5, 4]],
    )
    np.testing.assert_array_equal(reward_inputs(observation, 2), [[2, 3, 4, 7, 8]])


def test_render_modes():
    env = SafeGridWorld(seed=0, render_mode="ansi")
    env.reset(seed=0)
    text = env.render()
    grid = text.splitlines()[:10]
    assert sum(row.split().count("X") for row in grid) == 15
    assert sum(row.split().count("G") for row in grid) == 1
    image = SafeGridWorld(seed=0, render_mode="rgb_array")
    image.reset(seed=0)
    frame = image.render()
    assert frame.shape == (240, 240, 3) and frame.dtype == np.uint8


def test_distance_map_matches_the_cost_signal():
    env = SafeGridWorld(seed=6)
    dmap = env.distance_map()
    for x, y in [(0, 0), (3, 7), (9, 9)]:
        assert dmap[y, x] == pytest.approx(env.nearest_unsafe((x, y))[1])
    for x, y in env.unsafe_states:
        assert dmap[y, x] == 0


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(size=1), r"size must be an integer from 2 to 50 \(.*\), got size=1"),
        (dict(size=2.5), "size"),
        (dict(n_unsafe=0), "n_unsafe must be an integer from 1 to 19"),
        (dict(n_unsafe=20), r"n_unsafe must be an integer from 1 to 19.*10x10 placement area, got n_unsafe=20"),
        (dict(size=4, n_unsafe=3), "from 1 to 2"),
        (dict(size=10, n_unsafe=16, placement="reference"), r"from 1 to 15.*9x9 placement area"),
        (dict(d=0), "d must be a positive finite number"),
        (dict(d=-1.0), "d must be"),
        (dict(max_steps=0), r"max_steps must be an integer from 1 to 100000 or None \(.*\), got max_steps=0"),
        (dict(placement="edge"), "placement"),
        (dict(render_mode="human"), "render_mode"),
    ],
)
def test_bad_arguments_are_named(kwargs, match):
    with pytest.raises(ValueError, match=match):
        SafeGridWorld(**kwargs)


def test_a_cornered_placement_falls_back_to_a_chessboard_colour(monkeypatch):
    # as if the greedy draw cornered itself every time: the fallback alone must place and shift
    import sarsp_edu.world.gridworld.env as environment

    monkeypatch.setattr(environment, "PLACEMENT_ATTEMPTS", 0)  # the greedy draws the placement makes first
    for size, placement in [(4, "full"), (10, "full"), (10, "reference")]:
        n = SafeGridWorld.capacity(size, placement)
        for seed in range(10):
            env = SafeGridWorld(size=size, n_unsafe=n, placement=placement, seed=seed)
            env.reset(seed=seed)
            env.shift(n, rng=seed)
            unsafe = env.unsafe_states
            gaps = np.abs(unsafe[:, None, :] - unsafe[None, :, :]).sum(axis=2)
            assert np.all(gaps[~np.eye(n, dtype=bool)] >= 2)
            assert not {env.start, env.goal, env.agent_position} & {tuple(c) for c in unsafe.tolist()}


@pytest.mark.parametrize("action", [-1, 4, 1.0, "up", None, True])
def test_bad_actions_are_named(action):
    env = SafeGridWorld(seed=0)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action must be an integer in 0..3"):
        env.step(action)


def test_numpy_integer_actions_work():
    env = SafeGridWorld(seed=0)
    env.reset(seed=0)
    env.step(np.int64(2))


@pytest.mark.parametrize("nss", [-1, 16, 2.0])
def test_bad_switch_states(nss):
    with pytest.raises(ValueError, match="n_switch_states must be an integer from 0 to n_unsafe=15"):
        SafeGridWorld(seed=0).shift(nss)


def test_reset_options_are_checked():
    env = SafeGridWorld(seed=0)
    unsafe = tuple(int(v) for v in env.unsafe_states[0])
    with pytest.raises(ValueError, match="start must not be an unsafe state"):
        env.reset(options={"start": unsafe})
    with pytest.raises(ValueError, match="goal must lie on the grid"):
        env.reset(options={"goal": (10, 0)})
    with pytest.raises(ValueError, match="start and goal must differ"):
        free = next((x, y) for x in range(10) for y in range(10) if (x, y) not in map(tuple, env.unsafe_states))
        env.reset(options={"start": free, "goal": free})
    with pytest.raises(ValueError, match="options may hold"):
        env.reset(options={"agent": (0, 0)})
    for seed in range(30):  # a fixed start never collides with the drawn goal
        env.reset(seed=seed, options={"start": free})
        assert env.start == free != env.goal


def test_unsafe_states_are_read_only():
    env = SafeGridWorld(seed=0)
    with pytest.raises(ValueError):
        env.unsafe_states[0, 0] = 5


@pytest.mark.parametrize("placement", ["full", "reference"])
@pytest.mark.parametrize("size", [3, 4, 5, 7, 10])
def test_capacity_is_always_placed_and_shifted(size, placement):
    # the stated capacity must never fail to place, whatever the draw
    if SafeGridWorld.capacity(size, placement) < 1:
        with pytest.raises(ValueError, match=r"size must be at least 4 with placement='reference'"):
            SafeGridWorld(size=size, placement=placement)
        return
    n = SafeGridWorld.capacity(size, placement)
    for seed in range(8):
        env = SafeGridWorld(size=size, n_unsafe=n, placement=placement, seed=seed)
        for nss in sorted({0, 1, n // 2, n}):
            env.reset(seed=seed)
            env.shift(nss, rng=seed + 100)
            unsafe = env.unsafe_states
            gaps = np.abs(unsafe[:, None, :] - unsafe[None, :, :]).sum(axis=2)
            assert len(unsafe) == n and np.all(gaps[~np.eye(n, dtype=bool)] >= 2)  # none touch
    with pytest.raises(ValueError, match=rf"n_unsafe must be an integer from 1 to {n}, the most unsafe states"):
        SafeGridWorld(size=size, n_unsafe=n + 1, placement=placement)


def test_the_papers_capacity_and_the_spacing_limit():
    assert SafeGridWorld.capacity(10) == 19 and SafeGridWorld.capacity(10, "reference") == 15
    assert SafeGridWorld.max_unsafe(10) == 50  # a chessboard colour, which no shift could move
    with pytest.raises(ValueError, match="size must be at least 3 with placement='full'"):
        SafeGridWorld(size=2, n_unsafe=2)


def test_reset_seed_on_a_fresh_environment_reproduces_the_whole_world():
    # Gymnasium's convention; the layout was drawn unseeded in the constructor
    first, second = gym.make("sarsp_edu/SafeGridWorld-v0"), gym.make("sarsp_edu/SafeGridWorld-v0")
    obs_1, _ = first.reset(seed=3)
    obs_2, _ = second.reset(seed=3)
    assert np.array_equal(first.unwrapped.unsafe_states, second.unwrapped.unsafe_states)
    assert np.array_equal(obs_1, obs_2)
    # the same world as seeding the constructor, and later resets keep the layout
    seeded = SafeGridWorld(seed=3)
    assert np.array_equal(seeded.reset(seed=3)[0], obs_1)  # the same seed, the same episode
    assert np.array_equal(seeded.unsafe_states, first.unwrapped.unsafe_states)
    layout = first.unwrapped.unsafe_states
    first.reset(seed=4)
    assert np.array_equal(first.unwrapped.unsafe_states, layout)
    assert first.unwrapped.np_random_seed == 4 and seeded.np_random_seed == 3


# -- Gymnasium's conventions --------------------------------------------------------------------
def test_a_seeded_reset_gives_the_same_start_and_goal_every_time_the_first_time_too():
    import gymnasium

    env = gymnasium.make("sarsp_edu/SafeGridWorld-v0")
    first = env.reset(seed=0)[1]
    again = env.reset(seed=0)[1]
    assert (first["start"], first["goal"]) == (again["start"], again["goal"])
    other = env.reset(seed=1)[1]
    assert env.reset(seed=1)[1]["goal"] == other["goal"]
    # the world is the one the seed gives at construction, and stays for the later episodes
    np.testing.assert_array_equal(env.unwrapped.unsafe_states, SafeGridWorld(seed=0).unsafe_states)


def test_every_integer_like_action_the_space_accepts_is_taken():
    env = SafeGridWorld(seed=0)
    for action in (2, np.int64(2), np.array(2), np.array(2, dtype=np.int8)):
        env.reset(seed=3)
        assert env.action_space.contains(action)
        position = env.step(action)[0][:2]
        env.reset(seed=3)
        np.testing.assert_array_equal(position, env.step(2)[0][:2])
    env.reset(seed=3)
    for refused in (np.array(True), np.array(2.0), np.array([2]), 4):
        with pytest.raises(ValueError, match="action must be an integer in 0..3"):
            env.step(refused)


def test_the_registration_truncates_with_timelimit_where_the_environment_does():
    import gymnasium

    env = gymnasium.make("sarsp_edu/SafeGridWorld-v0")
    assert env.spec.max_episode_steps == 100 == SafeGridWorld().max_steps
    env.reset(seed=0)
    goal = env.unwrapped.goal
    steps, truncated, terminated = 0, False, False
    while not (truncated or terminated):
        # walk away from the goal along one wall, so that the episode can only end by the step limit
        action = 2 if goal[0] > 0 else 0
        _, _, terminated, truncated, _ = env.step(action)
        steps += 1
    assert truncated and not terminated and steps == 100


def test_vector_environments_seed_and_step_each_copy():
    import gymnasium

    envs = gymnasium.make_vec("sarsp_edu/SafeGridWorld-v0", num_envs=3, vectorization_mode="sync")
    observations, infos = envs.reset(seed=5)  # copies seeded 5, 6, 7: the worlds of those seeds
    assert observations.shape == (3, *envs.single_observation_space.shape)
    for i, seed in enumerate((5, 6, 7)):
        single = SafeGridWorld(seed=seed)
        np.testing.assert_array_equal(observations[i], single.reset(seed=seed)[0])
    for _ in range(120):  # past T_max: every copy ends an episode and starts the next by itself
        observations, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())
        assert observations.shape == (3, *envs.single_observation_space.shape) and rewards.shape == (3,)
    envs.close()
