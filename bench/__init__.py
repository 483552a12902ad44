"""Benchmarks: each of ours next to its raw-MuJoCo floor in the same run.

    python -m bench                      # the suite: prints ratios, writes a JSON
    python -m bench vector --json v.json
    python -m bench vector --against envpool,gymnasium    # with other libraries' Ant
    python -m bench suite --against envpool,gymnasium     # the Control Suite's, likewise
    python bench/bench_vector.py         # any one of them alone
    python -m bench.profiles step Reach  # where one operation's microseconds go (py-spy)

bench_parse (real files: parse, first call, write, write + compile vs MjSpec, lxml and
MuJoCo; dm_control's walkers from its wheel, `real_models`), bench_bind (bound reads and
writes vs numpy indexing), bench_env_step (Environment.step vs a raw mj_step loop; reset
time), bench_task_step (every shipped task's step and reset through gym.make vs raw
MuJoCo, with gymnasium's v5 environments), bench_attach (attach + compile of N copies vs
MjSpec), bench_scene (a 100-robot scene's memory vs its MjModel; to_xml_string + compile vs
MuJoCo's compile of the same text), bench_vector (VectorEnvironment at N = 1 to 128 vs
mujoco.batch, mujoco.rollout, SyncVectorEnvs, envpool; each side in its own process,
`workers`), bench_suite (the Control Suite's tasks the same way, against envpool's C++
suite). `bench.suite` runs them; timings never appear in tests. The `[bench]` extra
installs envpool and py-spy.
"""
