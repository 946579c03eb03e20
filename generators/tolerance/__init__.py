"""Profile tolerances that mean something: how a profile error wave moves the follower
(:mod:`.sensitivity`: the first-order gain, the contact-loss amplitude, the exact perturbed contact
solve) and the studies built on it (:mod:`.study`: the largest profile tolerance per wave count for
an acceleration limit, and the acceleration error of a measured deviation)."""
