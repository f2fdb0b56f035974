"""ngincompat.studies.findings.disc: the rules of section 3.3 on synthetic disc results."""

import numpy as np
import pytest
from studies.findings.test_rule import rule_of, run, section_tests

from ngincompat.studies.findings import AGREES, DIFFERS, PARTLY, disc

R = np.linspace(0.0, 1.0, 21)


def discs(sigma_r=1e-3 * (1 - R * R), sigma_theta=5e-4 * (1 - 2 * R * R), rim=1e-3,
          energies=(6.7e-6, 5.0e-6), circumferential=0.5, error=1e-16):
    """Radial fibers with these stresses; circumferential ones with the stresses scaled by
    ``circumferential``."""
    def one(scale, energy):
        return run({"b_eq22_error": error, "sigma_r_rim_rel": rim, "strain_energy": energy},
                   {"R": R, "sigma_r": scale * sigma_r, "sigma_theta": scale * sigma_theta})
    return {"disc-radial": one(1.0, energies[0]),
            "disc-circumferential": one(circumferential, energies[1])}


#: Per rule: verdict -> results that must give it.
CASES = {
    "disc-b": {AGREES: discs(), DIFFERS: discs(error=0.3)},
    "disc-fibers": {AGREES: discs(),
                    DIFFERS: discs(sigma_r=5e-4 * (1 - R * R), sigma_theta=1e-3 * (1 - R))},
    "disc-radial": {AGREES: discs(), DIFFERS: discs(sigma_r=-1e-3 * (1 - R * R))},
    "disc-theta": {AGREES: discs(), DIFFERS: discs(sigma_theta=-5e-4 * (1 - 2 * R * R))},
    "disc-energy": {AGREES: discs(), PARTLY: discs(circumferential=1.5),
                    DIFFERS: discs(circumferential=1.5, energies=(5.0e-6, 6.7e-6))},
}


test_every_rule_gives_every_verdict_it_lists, test_a_case_that_did_not_finish_is_not_judged = \
    section_tests(disc.FINDINGS, CASES)


def _rule(key):
    return rule_of(disc.FINDINGS, key)


@pytest.mark.parametrize("sigma_r, rim, failing", [
    (1e-3 * (1 - R * R), 0.2, "vanishing at the rim (0.2 of its largest)"),
    (1e-3 * R * R, 1e-3, "higher at the centre than at the rim"),
    (1e-3 * (1 - R * R) - 2e-4, 1e-3, "tension"),
])
def test_the_radial_stress_names_each_part_that_fails(sigma_r, rim, failing):
    """A rim stress above the traction-free tolerance, a stress rising outward, a stress in
    compression near the rim: each alone gives "differs" and is named."""
    _, verdict, reason = _rule("disc-radial").judge(discs(sigma_r=sigma_r, rim=rim))
    assert verdict == DIFFERS and reason == "not " + failing


def test_the_energy_rule_names_what_is_not_lower():
    _, verdict, reason = _rule("disc-energy").judge(discs(circumferential=1.5))
    assert verdict == PARTLY and reason == "does not hold: the stresses"
    _, verdict, reason = _rule("disc-energy").judge(discs(energies=(5.0e-6, 6.7e-6)))
    assert verdict == PARTLY and reason == "does not hold: the strain energy"
