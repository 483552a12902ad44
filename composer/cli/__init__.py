"""The `composer` command (`composer.cli.main(['list'])` from Python), in layers: a module
imports only its own layer and those before it, as tests/cli/test_cli_architecture.py checks:
    foundation:  errors arguments output progress video plot recipes catalog rollout describe
    contract:    engines.base engines.untrusted
    engines:     engines.sb3.files engines.sb3.encoder engines.sb3.policy engines.sb3.training
                 engines.sb3 engines.ray.files engines.ray.policy engines.ray.algorithm
                 engines.ray.instance engines.ray.training engines.ray
    registry:    engines
    commands:    run_folder listing show run view train evaluate
    entry:       main
"""

from composer.cli.main import main

__all__ = ["main"]
