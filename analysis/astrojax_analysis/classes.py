"""The orbit classes: name, whether circular, description and colour, indexed by the class
code of /windows/class. A format-3 sweep file carries them in /classes (written from the one
C++ table); for files of format 1 and 2 this is the fallback, the only copy in Python.

Colours: the Okabe–Ito palette, told apart with any colour vision; grey for the fallen bead.
Thresholds are drawn in black and grey only, so no threshold mark shares a class colour.
"""
from dataclasses import dataclass


@dataclass(frozen=True)
class OrbitClass:
    code: int
    name: str
    circular: bool
    description: str
    colour: str  # "#rrggbb"


FALLBACK = (
    OrbitClass(0, "fallen", False, "the bead fell onto the bottom ball", "#999999"),
    OrbitClass(1, "locked-circular", True, "circular orbit turning with the motor", "#0072B2"),
    OrbitClass(2, "lagging-circular", True, "circular orbit lagging behind the motor", "#009E73"),
    OrbitClass(3, "flower", False, "quasi-periodic orbit whose radius oscillates", "#CC79A7"),
    OrbitClass(4, "not-settled", False, "no steady orbit within the window", "#E69F00"),
    OrbitClass(5, "failed", False, "the integration failed", "#000000"),
)
# Classes of a steady orbit: where two of them meet at one ω_m, two orbits coexist.
STEADY_CLASSES = ("fallen", "locked-circular", "lagging-circular", "flower")
UNKNOWN_COLOUR = "k"  # a class code the table does not name


def colours(table):
    """{name: colour} in code order."""
    return {c.name: c.colour for c in table}


CLASS_COLOURS = colours(FALLBACK)
