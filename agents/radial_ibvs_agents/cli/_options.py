"""Command-line options shared by several commands."""

from __future__ import annotations

from typing import Any

__all__ = [
    "add_backend_options",
    "add_trust_model_option",
    "policies_help",
    "seed_value",
    "suites_help",
]


def seed_value(text: str) -> int:
    """``--seed``'s type: an integer from 0 to 2**63 - 1 (as Gymnasium and numpy take).

    Raises
    ------
    argparse.ArgumentTypeError
        For anything else (argparse prints it with the option's name and exits with 2).
    """
    import argparse

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text[:40]!r}") from None
    if not 0 <= value < 2**63:
        raise argparse.ArgumentTypeError(f"a seed is an integer from 0 to 2**63 - 1, got {value}")
    return value


def add_trust_model_option(parser: Any) -> None:
    """Add ``--trust-model``: the explicit opt-in to load a pickled stable-baselines3 model."""
    parser.add_argument(
        "--trust-model",
        action="store_true",
        help="allow a model directory that holds only a stable-baselines3 model.zip, loaded "
        "through its pickles, which can run code: only for models from a source you trust "
        "(models of this project need no such opt-in)",
    )


def add_backend_options(parser: Any, task: str) -> None:
    """Add ``--backend`` and ``--address`` (where the jobs run) to ``parser``.

    Parameters
    ----------
    parser
        An ``argparse`` parser.
    task
        What one Ray task runs, for the help text (e.g. ``"100-episode chunk"``).
    """
    from radial_ibvs_agents.experiments.backends import BACKENDS

    parser.add_argument(
        "--backend",
        choices=BACKENDS,
        default="local",
        help=f"local processes, or one Ray task per {task} (default: %(default)s)",
    )
    parser.add_argument(
        "--address",
        help="Ray cluster to join: 'auto' or HOST:PORT (default: a private local instance)",
    )


def policies_help() -> str:
    """Every policy by name, one line each, with the extra it needs (for ``--help``)."""
    from radial_ibvs_agents.analytic.registry import ANALYTIC_POLICIES, DESCRIPTIONS, EXTRAS
    from radial_ibvs_agents.learned import shipped_models

    def line(name: str, what: str) -> str:
        extra = f" [extra: {EXTRAS[name]}]" if name in EXTRAS else ""
        return f"  {name:<24} {what}{extra}"

    lines = ["policies (--policy NAME):"]
    lines += [line(name, DESCRIPTIONS.get(name, "")) for name in ANALYTIC_POLICIES]
    lines.append(line("random", "uniform random actions (a floor)"))
    lines += [line(name, SHIPPED.get(name, "a shipped learned model")) for name in shipped_models()]
    lines.append(
        line("./DIR", "a model directory (radial-ibvs train, radial_ibvs_agents.save_model_dir)")
    )
    lines.append('extras: pip install -e ".[EXTRA]"')
    return "\n".join(lines)


#: the shipped models, one line each (their metadata.json holds how each was made)
SHIPPED = {
    "dagger-student": "shipped: learned end to end, distilled from the planner (DAgger)",
}


def suites_help() -> str:
    """Every benchmark suite and its variants, one line each (for ``--help``)."""
    from radial_ibvs_agents.experiments.suites import SUITES

    lines = ["suites (--suites NAME ...):"]
    for name, variants in SUITES.items():
        labels = ", ".join(v.label for v in variants)
        lines.append(f"  {name:<14} {labels[:60] + ('...' if len(labels) > 60 else '')}")
    return "\n".join(lines)
