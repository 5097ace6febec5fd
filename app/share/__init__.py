"""Sharing a scene: a scenario as a short code and a link (``code``), the page script that hands a tab its
address and a link's scene (``link``, installed on the server), and the Share folder of a tab (``panel``).
"""
