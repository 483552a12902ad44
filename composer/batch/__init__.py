"""The batch protocol: a task's per-step methods written once, in batched form, run on a
batch of one environment or of many (`protocol`, where the contract is). `single` gives
one environment's `mjcf.Physics` as a batch of one (`composer.BatchOfOne`, what a
`composer.Environment` passes); `vector` gives a `VectorEnvironment`'s simulations as one
(`VectorPhysics`)."""
