"""The paper's published numbers (Tables III-VI), the only values not measured here.

Source: ../shared/reference/blind-navigation-paper.txt, section 5. Decimal
commas of Table IV are read as points. Keys are the mission files in
config/missions/ that re-create each test.
"""

#: Table III (sampled straight-line segments), per test: max distance travelled m,
#: set velocity SV m/s, RLV max, RLV min (m/s), RLV samples exceeding SV, total samples.
TABLE3 = {
    'table3_test1': {'distance': 3.315, 'sv': 0.05, 'rlv_max': 0.053, 'rlv_min': 0.036, 'over': 12, 'samples': 37},
    'table3_test2': {'distance': 3.219, 'sv': 0.08, 'rlv_max': 0.096, 'rlv_min': 0.066, 'over': 15, 'samples': 23},
    'table3_test3': {'distance': 3.221, 'sv': 0.12, 'rlv_max': 0.122, 'rlv_min': 0.083, 'over': 3, 'samples': 17},
    'table3_test4': {'distance': 3.375, 'sv': 0.20, 'rlv_max': 0.194, 'rlv_min': 0.160, 'over': 0, 'samples': 12},
    'table3_test5': {'distance': 3.401, 'sv': 0.25, 'rlv_max': 0.249, 'rlv_min': 0.209, 'over': 0, 'samples': 10},
}

#: Table IV (back travel with v only, w = 0), rows by forward velocity FV m/s:
#: forward ground-truth distance D m and heading HD rad, backward covered distance
#: CD m and heading HD rad, position error PE % and remaining distance RM m.
#: The paper has no 0.25 m/s row; its 0.110 m/s row has no Table III mission
#: (the 0.12 m/s mission is compared with its 0.121 row).
TABLE4 = [
    {'fv': 0.045, 'd': 3.331, 'hd': -0.0494, 'cd': 3.1, 'back_hd': -0.0546, 'pe': 6.93, 'rm': 0.231},
    {'fv': 0.080, 'd': 3.165, 'hd': -0.0504, 'cd': 2.971, 'back_hd': -0.0833, 'pe': 6.13, 'rm': 0.194},
    {'fv': 0.110, 'd': 3.252, 'hd': -0.0543, 'cd': 2.895, 'back_hd': -0.0408, 'pe': 10.98, 'rm': 0.357},
    {'fv': 0.121, 'd': 3.225, 'hd': -0.0312, 'cd': 2.981, 'back_hd': -0.0539, 'pe': 7.57, 'rm': 0.244},
    {'fv': 0.200, 'd': 3.387, 'hd': -0.0497, 'cd': 2.983, 'back_hd': -0.0367, 'pe': 11.93, 'rm': 0.404},
]
#: Table III mission -> the Table IV row it is compared with (by set velocity).
TABLE4_ROW = {'table3_test1': 0.045, 'table3_test2': 0.080, 'table3_test3': 0.121,
              'table3_test4': 0.200}

#: Table V (curved segment with obstacles): max distance m, set linear m/s and
#: angular rad/s velocity, RLV max/min m/s, RLV samples exceeding SV, total samples.
TABLE5 = {
    'table5_test1': {'distance': 3.5, 'sv': 0.086, 'asv': 0.096, 'rlv_max': 0.096, 'rlv_min': 0.006, 'over': 7, 'samples': 47},
    'table5_test2': {'distance': 3.4, 'sv': 0.086, 'asv': 0.096, 'rlv_max': 0.092, 'rlv_min': 0.021, 'over': 16, 'samples': 82},
    'table5_test3': {'distance': 3.01, 'sv': 0.069, 'asv': 0.087, 'rlv_max': 0.072, 'rlv_min': 0.019, 'over': 9, 'samples': 57},
}

#: Table VI (the layer on RTAB-Map vSLAM), LSV 0.086 m/s, ASV 0.097 rad/s:
#: max distance m, RLV samples above LSV, max RLV m/s, max / min RAV rad/s,
#: position error m, memory KB, total samples.
TABLE6 = {
    'table6_test1': {'distance': 2.6, 'over': 4, 'rlv_max': 0.093, 'rav_max': 0.135, 'rav_min': -0.071, 'error': 0.56, 'kb': 4, 'samples': 35},
    'table6_test2': {'distance': 3.8, 'over': 15, 'rlv_max': 0.096, 'rav_max': 0.042, 'rav_min': -0.044, 'error': 0.28, 'kb': 5, 'samples': 43},
    'table6_test3': {'distance': 5.6, 'over': 23, 'rlv_max': 0.096, 'rav_max': 0.074, 'rav_min': -0.054, 'error': 0.48, 'kb': 6, 'samples': 53},
    'table6_test4': {'distance': 6.8, 'over': 30, 'rlv_max': 0.102, 'rav_max': 0.033, 'rav_min': -0.043, 'error': 0.39, 'kb': 8, 'samples': 75},
    'table6_test5': {'distance': 8.4, 'over': 37, 'rlv_max': 0.098, 'rav_max': 0.055, 'rav_min': -0.042, 'error': 0.93, 'kb': 9, 'samples': 87},
    'table6_test6': {'distance': 13.2, 'over': 40, 'rlv_max': 0.100, 'rav_max': 0.09, 'rav_min': -0.064, 'error': 1.3, 'kb': 14, 'samples': 137},
}
TABLE6_LSV = 0.086
TABLE6_ASV = 0.097


def table4_row(mission):
    """The paper's Table IV row compared with a Table III mission, or None."""
    fv = TABLE4_ROW.get(mission)
    return next((row for row in TABLE4 if row['fv'] == fv), None)
