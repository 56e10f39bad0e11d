"""How the garment touches the body: contact laws and the skin.

* `cloth.contact.polyhedral`: frictionless contact with a mesh body (normal cones);
* `cloth.contact.tissue`: a soft-tissue (Winkler) layer under the skin;
* `cloth.contact.friction`: lagged, smoothed Coulomb friction on the skin;
* `cloth.contact.skin`: the skin models a case asks for, built and checked.
"""
