"""Follower kinds: each one module behind the interface of :mod:`.base`.
"""
