"""The manager's arithmetic (paper section 5.2): workload, workdone and priority of
voxels, equations 1-3, over each voxel's 3x3x3 neighbourhood.

  wl^c  corner table: 1 or 7 corners inside -> 0.25, 2 or 6 -> 0.5, 3 or 5 -> 0.75,
        4 -> 1.0; none (or all) inside but a sample found the surface -> 0.25
  wl^g  theta_i / Theta_max: the largest angle between the voxel's corner gradients over
        the largest such angle in the neighbourhood
  wl^d  the user's level of detail in [0, 1]
  (1)   wl_i  = (wl^c + wl^g + wl^d) / (wl^c_max + wl^g_max + wl^d_max)
  wd'_i = wd_i / wd_max, the voxel's sample tally over the neighbourhood's largest
  wd^g  = wl^g / 2^mu_i, mu_i the feature points found in the voxel plus trace steps
  (2)   wl'_i = (wl^c + wd^g + wl^d) / (wl^c_max + wl^g_max + wl^d_max)
  (3)   P_i   = wl_i - wl'_i * wd'_i
"""
import numpy as np

CORNER_TABLE = np.array([0.0, 0.25, 0.5, 0.75, 1.0, 0.75, 0.5, 0.25, 0.0])


def corner_workload(corners_in, surface_seen):
    wl = CORNER_TABLE[corners_in]
    return np.where(((corners_in == 0) | (corners_in == 8)) & surface_seen, 0.25, wl)


def priorities(bb, rows, lod):
    """Priority (and its terms) of the given voxel rows."""
    rows = np.asarray(rows, np.int64)
    v = bb.vox
    nb = bb.neighbours(rows)                      # (k, 27), -1 where absent

    def nmax(values):
        # an absent neighbour (-1) picks the appended last value, which counts for nothing
        return np.append(values, -np.inf)[nb].max(axis=1)

    wlc_all = corner_workload(v["corners_in"], v["surface"])
    theta = v["theta"]
    wlc = wlc_all[rows]
    theta_max = nmax(theta)
    wlg = np.where(theta_max > 0, theta[rows] / np.where(theta_max > 0, theta_max, 1), 0.0)
    wlg_max = np.where(theta_max > 0, 1.0, 0.0)   # the neighbourhood's own max over Theta_max
    wld = np.full(len(rows), float(lod))
    wlc_max = nmax(wlc_all)
    denom = wlc_max + wlg_max + wld
    denom = np.where(denom > 0, denom, 1.0)
    wl = (wlc + wlg + wld) / denom
    wd = v["samples"].astype(float)
    wd_max = nmax(wd)
    wdn = np.where(wd_max > 0, wd[rows] / np.where(wd_max > 0, wd_max, 1), 0.0)
    mu = v["features"][rows] + v["path_steps"][rows]
    wdg = wlg / np.power(2.0, np.minimum(mu, 1000))
    wl2 = (wlc + wdg + wld) / denom
    P = wl - wl2 * wdn
    return {"priority": P, "wl": wl, "wl_prime": wl2, "wd_prime": wdn, "wl_c": wlc, "wl_g": wlg,
            "wd_g": wdg}
