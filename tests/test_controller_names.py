"""Every controller name a door accepts is the core's (control/spec.rs): the kinds of
``ControllerSpec``, their hyphenated spellings, and the aliases of one table. The CLI's
``--controller`` choices, the campaigns' ``Scenario.controller`` names and the
``spacearm.control`` classes are checked against it here, so that a name added in one door and
not in the core fails."""

import argparse
import dataclasses

import pytest

from spacearm import _core, control
from spacearm.campaign import scenario as campaign_scenario
from spacearm.cli import (campaign as cli_campaign, capture as cli_capture, fmu as cli_fmu, plan as cli_plan,
                          simulate as cli_simulate)


def _controller_choices():
    """The choices of every ``--controller`` option of the CLI, by subcommand."""
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers(dest="command")
    cli_simulate.add_parsers(sub)
    cli_campaign.add_parser(sub)
    cli_capture.add_parser(sub)
    cli_plan.add_parser(sub)
    cli_fmu.add_parser(sub)
    out = {}
    for name, p in sub.choices.items():
        for action in p._actions:
            if action.dest == "controller" and action.choices:
                out[name] = list(action.choices)
    return out


def test_the_cli_offers_controllers_and_every_name_is_the_cores():
    choices = _controller_choices()
    assert {"simulate", "campaign", "fmu"} <= set(choices), choices
    for command, names in choices.items():
        for name in names:
            assert _core.controller_kind(name) in _core.CONTROLLER_KINDS, (command, name)


def test_the_campaign_names_are_the_cores():
    for kind in campaign_scenario._CONTROLLERS:
        assert kind in _core.CONTROLLER_KINDS
    default = next(f.default for f in dataclasses.fields(campaign_scenario.Scenario) if f.name == "controller")
    assert _core.controller_kind(default) in campaign_scenario._CONTROLLERS


def test_every_control_class_is_a_core_kind_and_every_kind_has_a_class():
    kinds = {cls._kind for cls in vars(control).values()
             if isinstance(cls, type) and issubclass(cls, control._Controller) and cls is not control._Controller}
    assert kinds == set(_core.CONTROLLER_KINDS) - {"none"}  # "none": controller=None


def test_names_resolve_through_one_table_and_unknown_ones_are_refused():
    assert _core.controller_kind("computed-torque") == "computed_torque"
    assert _core.controller_kind("ct") == "computed_torque"
    assert _core.controller_kind("pd") == "joint_pd"
    assert _core.controller_kind("coordinated") == "coordinated_flying"
    for alias, kind in _core.CONTROLLER_ALIASES.items():
        assert _core.controller_kind(alias) == kind and kind in _core.CONTROLLER_KINDS
    with pytest.raises(_core.ArgumentError, match="unknown controller 'lqr'"):
        _core.controller_kind("lqr")
    with pytest.raises(_core.ArgumentError, match="Scenario.controller must be"):
        campaign_scenario.Scenario(controller="lqr")
