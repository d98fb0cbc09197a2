"""The group contract with description files: every type declares its fields (each a
Field with a role, a unit and a description), which are optional, whether it drives, and
the pairs its fields make; those pairs are the joints the built groups close."""

from __future__ import annotations

from pathlib import Path

import pytest

from linkage_fmu import Description, groups, presets
from linkage_fmu.groups import ROLES, Field

EXAMPLE = Path(__file__).parents[1] / "examples" / "coupler_four_bar.toml"
UNITS = {"length": "m", "coordinate": "m", "vector": "m", "angle": "rad", "new link": "",
         "link": "", "point": "", "new point": "", "new joint": "", "branch": "",
         "link joints": "", "pose": "m"}


def descriptions():
    return [presets.preset(name) for name in presets.names()] + [Description.read(EXAMPLE)]


def old_pairs(cls, spec: dict) -> tuple:
    """The joint names the description checker derived before the contract had
    ``pairs`` (its code paths, by kind), for the specs it was right for."""
    kind, fields = cls.kind, {k: f.role for k, f in cls.FIELDS.items()}
    names = [spec.get(k) for k, r in fields.items()
             if r in ("point", "new point") and kind not in ("point",)]
    names += [spec[k] for k, r in fields.items() if r == "new joint" and k in spec]
    if kind == "crank":
        names = [spec.get("pivot")]
    if kind in ("RRP", "RPP"):
        names = [p for p in names if p != spec.get("ref")]
    return tuple(j for j in names if j is not None)


def test_a_role_implies_a_unit():
    assert set(ROLES) == set(UNITS)
    for role, unit in UNITS.items():
        assert Field(role, "x").unit == unit
        assert Field(role, "x").is_name == (role in ("new link", "link", "point", "new point",
                                                     "new joint"))
    with pytest.raises(ValueError, match="unknown field role 'mass'"):
        Field("mass", "mass of the link")
    with pytest.raises(AttributeError):
        Field("length", "x").role = "angle"  # frozen: the contract is read, not changed


@pytest.mark.parametrize("kind", sorted(groups.Group.registry))
def test_every_type_declares_its_contract(kind):
    cls = groups.Group.registry[kind]
    assert "FIELDS" in cls.__dict__
    assert all(isinstance(f, Field) and f.description for f in cls.FIELDS.values())
    assert set(cls.OPTIONAL) <= set(cls.FIELDS)
    assert isinstance(cls.DRIVER, bool)


def test_the_drivers_are_the_crank_and_the_cylinder():
    drivers = [k for k, cls in groups.Group.registry.items() if cls.DRIVER]
    assert drivers == ["crank", "cylinder"]


def test_fields_keep_the_order_of_messages():
    assert list(groups.RRR.FIELDS) == ["link1", "link2", "end1", "middle", "end2", "length1",
                                       "length2", "branch"]
    assert groups.RRR.FIELDS["length1"] == Field("length", "length of link1, from end1 to "
                                                            "middle")
    assert groups.LinkPoint.OPTIONAL == ("along", "across", "distance", "angle")


def test_pairs_are_the_joint_names_the_checker_used():
    """For every group of every shipped linkage, and with any one field left out."""
    count = 0
    for d in descriptions():
        for spec in d.groups:
            cls = groups.Group.registry[spec["type"]]
            for drop in [None, *cls.FIELDS]:
                part = {k: v for k, v in spec.items() if k != drop}
                assert cls.pairs(part) == old_pairs(cls, part), (spec, drop)
                count += 1
    assert count > 100


@pytest.mark.parametrize("name", presets.names())
def test_pairs_are_the_joints_of_the_built_groups(name):
    """What the checker takes for a group's pairs is what its Joint tuples name."""
    d, mech = presets.preset(name), presets.get(name)
    assert len(mech.groups) >= len(d.groups)
    for spec, grp in zip(d.groups, mech.groups):
        cls = type(grp)
        assert cls is groups.Group.registry[spec["type"]]
        pairs = cls.pairs(spec)
        assert len(set(pairs)) == len(pairs)
        assert sorted(pairs) == sorted(j.name for j in grp.joints), spec
    assert sorted(j.name for j in mech.joints) == sorted(
        j for spec in d.groups for j in groups.Group.registry[spec["type"]].pairs(spec))


def test_pairs_take_only_names():
    """A field given as something else than a name makes no pair (the checker reports it)."""
    spec = {"type": "RRR", "link1": "2", "link2": "3", "end1": ["B"], "middle": "",
            "end2": "D"}
    assert groups.RRR.pairs(spec) == ("D",)
    assert groups.RPP.pairs({"pin": "B", "ref": "S3", "slot": "s", "guide": "g"}) == (
        "B", "s", "g")
    assert groups.LinkPoint.pairs({"link": "2", "from": "B", "name": "P"}) == ()
