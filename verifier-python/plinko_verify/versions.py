"""The constants of every shipped engine version (docs/engine-spec.md, section 1)."""

from .multipliers import MULTIPLIERS

# Shared by every shipped version (section 1.1).
SOLVER = {
    'gravity': 980.0,
    'timestep': 1 / 60,
    'restitution_threshold': 30.0,
    'linear_slop': 0.05,
    'correction_fraction': 0.8,
    'max_travel_per_substep': 1.0,
    'max_substeps': 16,
    'max_impacts_per_substep': 4,
}

VERSIONS = {
    '1.0.0': {
        'geometry': {
            'peg_radius': 4.0, 'ball_radius': 7.0, 'peg_spacing': 36.0, 'row_spacing': 32.0,
            'side_margin': 24.0, 'drop_height': 32.0, 'drop_zone_half_width': 9.0, 'bucket_depth': 20.0,
        },
        'ball': {'density': 7.8, 'restitution': 0.4, 'friction': 0.2},
        'peg': {'density': 1.2, 'restitution': 0.45, 'friction': 0.3},
        'release': {'max_vx': 20.0, 'max_vy': 20.0, 'max_spin': 3.0},
        'max_drop_ticks': 3600,
    },
    '2.0.0': {
        'geometry': {
            'peg_radius': 1.25, 'ball_radius': 2.0, 'peg_spacing': 8.0, 'row_spacing': 7.0,
            'side_margin': 8.0, 'drop_height': 7.0, 'drop_zone_half_width': 2.0, 'bucket_depth': 5.0,
        },
        'ball': {'density': 7.8, 'restitution': 0.4, 'friction': 0.2},
        'peg': {'density': 1.2, 'restitution': 0.4, 'friction': 0.3},
        'release': {'max_vx': 4.0, 'max_vy': 4.0, 'max_spin': 3.0},
        'max_drop_ticks': 3600,
    },
}

ENGINE_VERSIONS = tuple(VERSIONS)
ENGINE_VERSION = ENGINE_VERSIONS[-1]
MIN_ROWS = 8
MAX_ROWS = 16
RISKS = ('low', 'medium', 'high')


def multipliers(version, rows, risk):
    return MULTIPLIERS[version][rows][risk]
