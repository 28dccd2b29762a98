"""/bonds/split_tn, split_tt: per bond point, the traction of the pair that decided
its split (icerubble/run/split_traction.py), on a pair table computed by hand."""
import numpy as np
import pytest

from icerubble.run.split_traction import point_split_traction

SIGMA, TAU = 10e3, 50e3   # Pa, beta = 5


def _table():
    """Point 0: one pair. Point 1 (a junction): pair A in tension, t_e = 9 kPa, and pair
    B under compression, t_e = (|t_t| - mu |t_n|)/beta = (60 - 2 mu)/5 kPa. Point 2:
    two pairs with equal t_e. Point 3: never split (NaN)."""
    pair_point = np.array([0, 1, 1, 2, 2, 3])
    tn = np.array([5e3, 9e3, -2e3, 4e3, 4e3, np.nan])
    tt = np.array([1e3, 0.0, 60e3, 3e3, -3e3, np.nan])
    return pair_point, tn, tt, np.full(4, SIGMA), np.full(4, TAU)


def test_the_pair_with_the_largest_effective_traction_speaks_for_its_point():
    pair_point, tn, tt, s, t = _table()
    out_tn, out_tt = point_split_traction(pair_point, tn, tt, s, t, mu=0.3)
    # point 1: B has t_e = 11.88 kPa > A's 9 kPa; point 2: a tie, the first pair
    assert out_tn[:3].tolist() == [5e3, -2e3, 4e3] and out_tt[:3].tolist() == [1e3, 60e3, 3e3]
    assert np.isnan(out_tn[3]) and np.isnan(out_tt[3])
    # with mu = 10, B's t_e is (60 - 20)/5 = 8 kPa < 9 kPa: A decided the split
    out_tn, out_tt = point_split_traction(pair_point, tn, tt, s, t, mu=10.0)
    assert (out_tn[1], out_tt[1]) == (9e3, 0.0)


def test_bad_pair_table_is_refused():
    pair_point, tn, tt, s, t = _table()
    with pytest.raises(ValueError, match=r"pair_point must lie in \[0, 3\)"):
        point_split_traction(pair_point, tn, tt, s[:3], t[:3], mu=0.3)
    with pytest.raises(ValueError, match="one entry per pair"):
        point_split_traction(pair_point, tn[:-1], tt, s, t, mu=0.3)
