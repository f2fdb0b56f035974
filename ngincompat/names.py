"""The names the program knows, written once: its scenes, the axon fields of section 3.7 and
the expanders' footprints of section 3.6.

Plain tuples, no NGSolve: the command line's help, the geometries and every layer take their
lists from here (the scene classes are registered under these names in
:data:`ngincompat.scenes.SCENES`).
"""

#: The scenes ``ngincompat run`` takes: the paper's sections in order, then a mesh and
#: growth field of the user's own (custom), then the brain (atrophy).
SCENES = ("cube", "hemisphere", "disc", "cylinder", "skin", "folding", "custom", "atrophy")

#: The axon fields of Fig. 7a, its columns from left to right: curved outward (meeting the
#: interface tangentially), concentric and straight (both normal to the cortex).
AXONS = ("curved", "concentric", "straight")

#: The shapes of the expander's footprint of Fig. 6.
FOOTPRINTS = ("rectangle", "circle", "square", "crescent")
