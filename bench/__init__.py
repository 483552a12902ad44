"""Benchmarks: each of ours next to its raw-MuJoCo floor, measured in the same process.

    python -m bench                      # the suite: prints ratios, writes a JSON
    python -m bench vector --json v.json
    python bench/bench_vector.py         # any one of them alone

bench_parse (parse, write, write + compile vs MjSpec, lxml and MuJoCo), bench_bind
(bound reads and writes vs numpy indexing), bench_env_step (Environment.step vs a raw
mj_step loop; reset time), bench_attach (attach + compile of N copies vs MjSpec),
bench_scene (a 100-robot scene's memory vs its MjModel; to_xml_string + compile vs
MuJoCo's compile of the same text), bench_vector (VectorEnvironment vs mujoco.batch and
vs SyncVectorEnv). `bench.suite` runs them; timings never appear in tests.
"""
