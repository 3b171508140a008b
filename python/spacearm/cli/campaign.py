"""``spacearm campaign MODEL --samples N ...``: an inertia-uncertainty Monte Carlo campaign, or
with ``--capture-contact`` a capture-on-contact campaign over approach errors
([`spacearm.campaign.run_capture_campaign`][spacearm.campaign.run_capture_campaign]: MODEL's
gripper closing on a tumbling handle, the success rate with its Wilson interval in the table).

Runs [`spacearm.campaign.run_campaign`][spacearm.campaign.run_campaign] on native threads (``--workers``) or on a Dask
cluster (``--scheduler tcp://host:8786``, with ``--worker-timeout``), writes the results to ``--out`` (.npz, atomically,
resumable), prints the metrics table and optionally draws ``--plot``.
"""

from __future__ import annotations

import sys

from .model_options import add_model_arguments

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:

    p = sub.add_parser("campaign", help="Monte Carlo campaign: tracking cost of inertia errors (threads or Dask)",
                       description="MODEL with its model options is the nominal model; the workers receive it whole "
                                   "(as model-file text in the campaign spec), so a mounted URDF arm runs as loaded here.")
    add_model_arguments(p)
    p.add_argument("--samples", type=int, required=True, help="number of samples")
    p.add_argument("--seed", type=int, default=0, help="campaign seed (default 0)")
    p.add_argument("--workers", type=int, default=None,
                   help="threads running the samples as native rollouts (default: CPU count; 0 = one by one in the "
                        "main thread)")
    p.add_argument("--scheduler", default=None, help="Dask scheduler address (tcp://host:port) to run on a cluster")
    p.add_argument("--batch-size", type=int, default=None,
                   help="samples per batch (default: 8 per thread; with --scheduler about 4 tasks per worker thread, "
                        "at most 64)")
    p.add_argument("--worker-timeout", type=float, default=None,
                   help="with --scheduler: stop when the cluster has had no live worker for this long, s (default 60); "
                        "the samples not run stay pending in --out")
    p.add_argument("--out", default="campaign.npz", help="result file (.npz; default campaign.npz); resumed if it exists")
    p.add_argument("--no-resume", action="store_true", help="overwrite --out instead of resuming it")
    p.add_argument("--retry-failed", action="store_true", help="when resuming, run failed samples again")
    p.add_argument("--plot", default=None, help="write the campaign figure (PNG)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    s = p.add_argument_group("scenario")
    s.add_argument("--mode", default="floating", help="maneuvering mode (default floating)")
    s.add_argument("--controller", default="computed-torque", choices=("computed-torque", "pd"))
    s.add_argument("--duration", type=float, default=None, help="s (default 4; with --capture-contact 3)")
    s.add_argument("--dt", type=float, default=None, help="RK4 step, s (default 0.002; with --capture-contact 0.0005)")
    s.add_argument("--q-offset", type=float, default=0.5, help="goal = initial q + this, rad (default 0.5)")
    s.add_argument("--kp", type=float, default=100.0)
    s.add_argument("--kd", type=float, default=20.0)
    s.add_argument("--flexibility", default=None, metavar="FILE.toml",
                   help="flexible plants: a TOML file with a [tank] and/or a [panel] table and the drawn parameters "
                        "(fill_fraction = {kind = \"uniform\", low = 0.3, high = 0.7}, ...; docs/campaigns.md)")
    s.add_argument("--cmg", default=None, metavar="FILE.toml",
                   help="CMG parameters drawn per sample: a TOML file with wheel_speed, rotor_inertia_scale and/or "
                        "gimbal_misalignment, each a number or {kind = \"uniform\", low = 100.0, high = 600.0}, ... "
                        "(docs/campaigns.md)")
    from .simulate import add_orbit_options

    add_orbit_options(p)
    k = p.add_argument_group("capture on contact (docs/campaigns.md, \"A capture-on-contact campaign\")")
    k.add_argument("--capture-contact", action="store_true",
                   help="fly MODEL's gripper closing on a tumbling box's handle by contact over drawn approach errors; "
                        "the table gives the success rate (held) with its 95%% Wilson interval")
    k.add_argument("--gripper", default=None, help="with --capture-contact: the gripper (default MODEL's only one)")
    k.add_argument("--spin", default="0.05", metavar="LOW[,HIGH]",
                   help="with --capture-contact: the target's spin rate about its handle, uniform in [LOW, HIGH], rad/s "
                        "(default 0.05)")
    k.add_argument("--offset-sigma", type=float, default=0.0,
                   help="with --capture-contact: std of each component of the handle's offset from the grasp centre, m")
    k.add_argument("--attitude-sigma", type=float, default=0.0,
                   help="with --capture-contact: std of each component of the target's attitude error, rad")
    k.add_argument("--friction", type=float, default=0.5, help="with --capture-contact: Coulomb's mu (default 0.5)")
    k.add_argument("--plot-against", default="spin", choices=("spin", "offset", "attitude"),
                   help="with --capture-contact and --plot: the success rate against this (default spin)")
    e = p.add_argument_group("inertia errors")
    e.add_argument("--base-mass-sigma", type=float, default=0.05, help="log-std of the base mass scale (default 0.05)")
    e.add_argument("--base-inertia-sigma", type=float, default=0.10, help="log-std of the base inertia scale (default 0.10)")
    e.add_argument("--link-mass-sigma", type=float, default=0.02, help="log-std of the link mass scale (default 0.02)")
    e.add_argument("--slosh-fraction-max", type=float, default=0.05, help="max fraction of base mass displaced (default 0.05)")
    e.add_argument("--slosh-offset", type=float, default=0.5, help="distance of the displaced mass, m (default 0.5)")
    e.add_argument("--payload-mass-max", type=float, default=0.0, help="max payload at the end effector, kg (default 0)")


def _recipe(path, option: str, recipe, known):
    """``recipe.from_dict`` of a TOML file whose keys are among ``known`` (the recipe's
    ``to_dict()`` keys); data only, read by the standard library's TOML parser."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python < 3.11
        import tomli as tomllib
    from ..errors import ArgumentError, ModelFileError

    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise ModelFileError(f"{option}: cannot read {path}: {exc.strerror}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ModelFileError(f"{option}: {path} is not valid TOML: {exc}") from None
    unknown = sorted(set(data) - set(known))
    if unknown:
        raise ArgumentError(f"{option}: {path}: unknown key(s) {unknown}; expected some of {sorted(known)}")
    try:
        return recipe.from_dict(data)
    except TypeError as exc:  # a table with a key the recipe's parts or distributions do not take
        raise ArgumentError(f"{option}: {path}: {exc}") from None


def _flexibility(path):
    """The [`Flexibility`][spacearm.campaign.Flexibility] recipe of a TOML file: its tables and
    keys are `Flexibility.to_dict()`'s (``[tank]``, ``[panel]``, and each drawn parameter as
    ``{kind = ..., ...}``)."""
    from ..campaign import Flexibility

    known = {"tank", "panel", "fill_fraction", "slosh_frequency_scale", "slosh_damping_ratio", "panel_stiffness"}
    return _recipe(path, "--flexibility", Flexibility, known)


def _cmg(path):
    """The [`CmgUncertainty`][spacearm.campaign.CmgUncertainty] of a TOML file: the keys of
    `CmgUncertainty.to_dict()`, each a number or ``{kind = ..., ...}``."""
    from ..campaign import CmgUncertainty

    return _recipe(path, "--cmg", CmgUncertainty, {"wheel_speed", "rotor_inertia_scale", "gimbal_misalignment"})


def _run_capture(args, robot, out) -> None:
    """``--capture-contact``: the capture-on-contact campaign."""
    from ..campaign import ApproachErrors, run_capture_campaign
    from ..capture import ContactCapture
    from .numbers import CliError, parse_numbers

    for flag, given in (("--scheduler", args.scheduler), ("--flexibility", args.flexibility), ("--cmg", args.cmg),
                        ("--orbit", args.orbit), ("--batch-size", args.batch_size), ("--worker-timeout", args.worker_timeout)):
        if given is not None:
            raise CliError(f"{flag} is for the inertia-uncertainty campaign; --capture-contact runs its samples in this "
                           "process and does not take it")
    if args.workers not in (None, 0, 1):
        raise CliError("--capture-contact runs its samples one by one in this process; --workers is not taken")
    spin = parse_numbers(args.spin, "--spin", None, "LOW[,HIGH]", "rad/s")
    if len(spin) not in (1, 2):
        raise CliError(f"--spin takes LOW or LOW,HIGH, got {len(spin)} numbers")
    errors = ApproachErrors(offset_sigma=args.offset_sigma, attitude_sigma=args.attitude_sigma, spin_low=spin[0],
                            spin_high=spin[-1])
    capture = ContactCapture(friction=args.friction, **({} if args.duration is None else {"duration": args.duration}),
                             **({} if args.dt is None else {"dt": args.dt}))
    if args.retry_failed:
        raise CliError("--retry-failed is for the inertia-uncertainty campaign; a failed capture sample fails again")
    result = run_capture_campaign(robot, args.samples, seed=args.seed, errors=errors, capture=capture, gripper=args.gripper,
                                  out=args.out, resume=not args.no_resume, progress=not args.no_progress)
    _report(result, args, out, lambda path: result.plot(path, parameter=args.plot_against))


def run(args, model_from_args, out=None) -> None:
    from ..campaign import Perturbations, Scenario, run_campaign
    from ..errors import SpacearmError

    out = sys.stdout if out is None else out
    from .simulate import orbit_from_args

    robot = model_from_args(args)
    if args.capture_contact:
        return _run_capture(args, robot, out)
    args.duration = 4.0 if args.duration is None else args.duration
    args.dt = 2e-3 if args.dt is None else args.dt
    orbit = orbit_from_args(args)
    try:
        perturbations = Perturbations(args.base_mass_sigma, args.base_inertia_sigma, args.link_mass_sigma,
                                      args.slosh_fraction_max, args.slosh_offset, args.payload_mass_max)
        scenario = Scenario(mode=args.mode, controller=args.controller, duration=args.duration, dt=args.dt,
                            q_offset=args.q_offset, kp=args.kp, kd=args.kd, orbit=orbit,
                            gravity_gradient=orbit is None or not args.no_gravity_gradient,
                            flexibility=None if args.flexibility is None else _flexibility(args.flexibility),
                            cmg=None if args.cmg is None else _cmg(args.cmg))
        result = run_campaign(robot, args.samples, seed=args.seed, perturbations=perturbations, scenario=scenario,
                              workers=args.workers, scheduler=args.scheduler, batch_size=args.batch_size,
                              worker_timeout=args.worker_timeout, out=args.out,
                              resume=not args.no_resume, retry_failed=args.retry_failed,
                              progress=not args.no_progress)
    except SpacearmError:
        raise
    except ValueError as exc:  # bad option values: reported like every other CLI error
        raise SpacearmError(str(exc)) from None
    _report(result, args, out, result.plot)


def _report(result, args, out, plot) -> None:
    """Print a campaign's summary, where it is saved, its failures and its figure (``plot(path)``);
    every sample failed (none pending) is a ``CliError``."""
    out.write(result.summary() + "\n")
    out.write(f"results: {args.out}\n")
    failures = result.failures()
    if failures:
        first = next(iter(failures.items()))
        out.write(f"{len(failures)} sample(s) failed; e.g. sample {first[0]}: {first[1]}\n")
    if args.plot:
        if result.n_ok:
            plot(args.plot)
            out.write(f"figure: {args.plot}\n")
        else:
            out.write("no sample ran successfully: no figure written\n")
    if failures and not result.n_ok and not result.n_pending:
        from .numbers import CliError

        raise CliError(f"every sample of the campaign failed ({len(failures)} of {len(failures)}; the record is {args.out}): "
                       f"e.g. sample {first[0]}: {first[1]}")
