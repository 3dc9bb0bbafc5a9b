#include "radiance/lebedev_quadrature.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rad {

namespace {

// The orbits of the octahedral group O_h on the sphere used by Lebedev's rules. Each rule is a
// list of orbits; every point of an orbit carries the same weight. In Laikov's code these are the
// "gen_oh" codes 1..6, with the orbit parameters named a_1, a_2, a_3, b_k, c_k, d_k in the paper.
enum class OrbitKind {
    Vertex,        // (1, 0, 0) and its images: 6 points (octahedron vertices, "a1")
    EdgeMidpoint,  // (0, 1, 1)/sqrt(2): 12 points ("a2")
    FaceCentre,    // (1, 1, 1)/sqrt(3): 8 points ("a3")
    AAB,           // (a, a, b), b = sqrt(1 - 2a^2): 24 points ("b_k")
    AB0,           // (a, b, 0), b = sqrt(1 - a^2): 24 points ("c_k")
    ABC,           // (a, b, c), c = sqrt(1 - a^2 - b^2): 48 points ("d_k")
};

struct Orbit {
    OrbitKind kind;
    double a, b;  // free parameters (unused ones are 0)
    double v;     // weight of each point, normalised so that the rule's weights sum to 1
};

struct RuleTable {
    int pointCount;
    int precision;
    const Orbit* orbits;
    std::size_t orbitCount;
};

// ---- Data: orbit parameters and weights transcribed from Lebedev & Laikov (1999) / Laikov's code.
// Each line: orbit kind, a, b, weight (sum over all points = 1).
// 6 points, precision 3.
const Orbit kRule6[] = {
    {OrbitKind::Vertex, 0, 0, 0.1666666666666667},
};
// 14 points, precision 5.
const Orbit kRule14[] = {
    {OrbitKind::Vertex, 0, 0, 0.6666666666666667e-01},
    {OrbitKind::FaceCentre, 0, 0, 0.7500000000000000e-01},
};
// 26 points, precision 7.
const Orbit kRule26[] = {
    {OrbitKind::Vertex, 0, 0, 0.4761904761904762e-01},
    {OrbitKind::EdgeMidpoint, 0, 0, 0.3809523809523810e-01},
    {OrbitKind::FaceCentre, 0, 0, 0.3214285714285714e-01},
};
// 38 points, precision 9.
const Orbit kRule38[] = {
    {OrbitKind::Vertex, 0, 0, 0.9523809523809524e-02},
    {OrbitKind::FaceCentre, 0, 0, 0.3214285714285714e-01},
    {OrbitKind::AB0, 0.4597008433809831, 0, 0.2857142857142857e-01},
};
// 50 points, precision 11.
const Orbit kRule50[] = {
    {OrbitKind::Vertex, 0, 0, 0.1269841269841270e-01},
    {OrbitKind::EdgeMidpoint, 0, 0, 0.2257495590828924e-01},
    {OrbitKind::FaceCentre, 0, 0, 0.2109375000000000e-01},
    {OrbitKind::AAB, 0.3015113445777636, 0, 0.2017333553791887e-01},
};
// 74 points, precision 13.
const Orbit kRule74[] = {
    {OrbitKind::Vertex, 0, 0, 0.5130671797338464e-03},
    {OrbitKind::EdgeMidpoint, 0, 0, 0.1660406956574204e-01},
    {OrbitKind::FaceCentre, 0, 0, -0.2958603896103896e-01},
    {OrbitKind::AAB, 0.4803844614152614, 0, 0.2657620708215946e-01},
    {OrbitKind::AB0, 0.3207726489807764, 0, 0.1652217099371571e-01},
};
// 86 points, precision 15.
const Orbit kRule86[] = {
    {OrbitKind::Vertex, 0, 0, 0.1154401154401154e-01},
    {OrbitKind::FaceCentre, 0, 0, 0.1194390908585628e-01},
    {OrbitKind::AAB, 0.3696028464541502, 0, 0.1111055571060340e-01},
    {OrbitKind::AAB, 0.6943540066026664, 0, 0.1187650129453714e-01},
    {OrbitKind::AB0, 0.3742430390903412, 0, 0.1181230374690448e-01},
};
// 110 points, precision 17.
const Orbit kRule110[] = {
    {OrbitKind::Vertex, 0, 0, 0.3828270494937162e-02},
    {OrbitKind::FaceCentre, 0, 0, 0.9793737512487512e-02},
    {OrbitKind::AAB, 0.1851156353447362, 0, 0.8211737283191111e-02},
    {OrbitKind::AAB, 0.6904210483822922, 0, 0.9942814891178103e-02},
    {OrbitKind::AAB, 0.3956894730559419, 0, 0.9595471336070963e-02},
    {OrbitKind::AB0, 0.4783690288121502, 0, 0.9694996361663028e-02},
};
// 146 points, precision 19.
const Orbit kRule146[] = {
    {OrbitKind::Vertex, 0, 0, 0.5996313688621381e-03},
    {OrbitKind::EdgeMidpoint, 0, 0, 0.7372999718620756e-02},
    {OrbitKind::FaceCentre, 0, 0, 0.7210515360144488e-02},
    {OrbitKind::AAB, 0.6764410400114264, 0, 0.7116355493117555e-02},
    {OrbitKind::AAB, 0.4174961227965453, 0, 0.6753829486314477e-02},
    {OrbitKind::AAB, 0.1574676672039082, 0, 0.7574394159054034e-02},
    {OrbitKind::ABC, 0.1403553811713183, 0.4493328323269557, 0.6991087353303262e-02},
};
// 170 points, precision 21.
const Orbit kRule170[] = {
    {OrbitKind::Vertex, 0, 0, 0.5544842902037365e-02},
    {OrbitKind::EdgeMidpoint, 0, 0, 0.6071332770670752e-02},
    {OrbitKind::FaceCentre, 0, 0, 0.6383674773515093e-02},
    {OrbitKind::AAB, 0.2551252621114134, 0, 0.5183387587747790e-02},
    {OrbitKind::AAB, 0.6743601460362766, 0, 0.6317929009813725e-02},
    {OrbitKind::AAB, 0.4318910696719410, 0, 0.6201670006589077e-02},
    {OrbitKind::AB0, 0.2613931360335988, 0, 0.5477143385137348e-02},
    {OrbitKind::ABC, 0.4990453161796037, 0.1446630744325115, 0.5968383987681156e-02},
};
// 194 points, precision 23.
const Orbit kRule194[] = {
    {OrbitKind::Vertex, 0, 0, 0.1782340447244611e-02},
    {OrbitKind::EdgeMidpoint, 0, 0, 0.5716905949977102e-02},
    {OrbitKind::FaceCentre, 0, 0, 0.5573383178848738e-02},
    {OrbitKind::AAB, 0.6712973442695226, 0, 0.5608704082587997e-02},
    {OrbitKind::AAB, 0.2892465627575439, 0, 0.5158237711805383e-02},
    {OrbitKind::AAB, 0.4446933178717437, 0, 0.5518771467273614e-02},
    {OrbitKind::AAB, 0.1299335447650067, 0, 0.4106777028169394e-02},
    {OrbitKind::AB0, 0.3457702197611283, 0, 0.5051846064614808e-02},
    {OrbitKind::ABC, 0.1590417105383530, 0.8360360154824589, 0.5530248916233094e-02},
};
// 230 points, precision 25.
const Orbit kRule230[] = {
    {OrbitKind::Vertex, 0, 0, -0.5522639919727325e-01},
    {OrbitKind::FaceCentre, 0, 0, 0.4450274607445226e-02},
    {OrbitKind::AAB, 0.4492044687397611, 0, 0.4496841067921404e-02},
    {OrbitKind::AAB, 0.2520419490210201, 0, 0.5049153450478750e-02},
    {OrbitKind::AAB, 0.6981906658447242, 0, 0.3976408018051883e-02},
    {OrbitKind::AAB, 0.6587405243460960, 0, 0.4401400650381014e-02},
    {OrbitKind::AAB, 0.4038544050097660e-01, 0, 0.1724544350544401e-01},
    {OrbitKind::AB0, 0.5823842309715585, 0, 0.4231083095357343e-02},
    {OrbitKind::AB0, 0.3545877390518688, 0, 0.5198069864064399e-02},
    {OrbitKind::ABC, 0.2272181808998187, 0.4864661535886647, 0.4695720972568883e-02},
};
// 266 points, precision 27.
const Orbit kRule266[] = {
    {OrbitKind::Vertex, 0, 0, -0.1313769127326952e-02},
    {OrbitKind::EdgeMidpoint, 0, 0, -0.2522728704859336e-02},
    {OrbitKind::FaceCentre, 0, 0, 0.4186853881700583e-02},
    {OrbitKind::AAB, 0.7039373391585475, 0, 0.5315167977810885e-02},
    {OrbitKind::AAB, 0.1012526248572414, 0, 0.4047142377086219e-02},
    {OrbitKind::AAB, 0.4647448726420539, 0, 0.4112482394406990e-02},
    {OrbitKind::AAB, 0.3277420654971629, 0, 0.3595584899758782e-02},
    {OrbitKind::AAB, 0.6620338663699974, 0, 0.4256131351428158e-02},
    {OrbitKind::AB0, 0.8506508083520399, 0, 0.4229582700647240e-02},
    {OrbitKind::ABC, 0.3233484542692899, 0.1153112011009701, 0.4080914225780505e-02},
    {OrbitKind::ABC, 0.2314790158712601, 0.5244939240922365, 0.4071467593830964e-02},
};
// 302 points, precision 29.
const Orbit kRule302[] = {
    {OrbitKind::Vertex, 0, 0, 0.8545911725128148e-03},
    {OrbitKind::FaceCentre, 0, 0, 0.3599119285025571e-02},
    {OrbitKind::AAB, 0.3515640345570105, 0, 0.3449788424305883e-02},
    {OrbitKind::AAB, 0.6566329410219612, 0, 0.3604822601419882e-02},
    {OrbitKind::AAB, 0.4729054132581005, 0, 0.3576729661743367e-02},
    {OrbitKind::AAB, 0.9618308522614784e-01, 0, 0.2352101413689164e-02},
    {OrbitKind::AAB, 0.2219645236294178, 0, 0.3108953122413675e-02},
    {OrbitKind::AAB, 0.7011766416089545, 0, 0.3650045807677255e-02},
    {OrbitKind::AB0, 0.2644152887060663, 0, 0.2982344963171804e-02},
    {OrbitKind::AB0, 0.5718955891878961, 0, 0.3600820932216460e-02},
    {OrbitKind::ABC, 0.2510034751770465, 0.8000727494073952, 0.3571540554273387e-02},
    {OrbitKind::ABC, 0.1233548532583327, 0.4127724083168531, 0.3392312205006170e-02},
};
// 350 points, precision 31.
const Orbit kRule350[] = {
    {OrbitKind::Vertex, 0, 0, 0.3006796749453936e-02},
    {OrbitKind::FaceCentre, 0, 0, 0.3050627745650771e-02},
    {OrbitKind::AAB, 0.7068965463912316, 0, 0.1621104600288991e-02},
    {OrbitKind::AAB, 0.4794682625712025, 0, 0.3005701484901752e-02},
    {OrbitKind::AAB, 0.1927533154878019, 0, 0.2990992529653774e-02},
    {OrbitKind::AAB, 0.6930357961327123, 0, 0.2982170644107595e-02},
    {OrbitKind::AAB, 0.3608302115520091, 0, 0.2721564237310992e-02},
    {OrbitKind::AAB, 0.6498486161496169, 0, 0.3033513795811141e-02},
    {OrbitKind::AB0, 0.1932945013230339, 0, 0.3007949555218533e-02},
    {OrbitKind::AB0, 0.3800494919899303, 0, 0.2881964603055307e-02},
    {OrbitKind::ABC, 0.2899558825499574, 0.7934537856582316, 0.2958357626535696e-02},
    {OrbitKind::ABC, 0.9684121455103957e-01, 0.8280801506686862, 0.3036020026407088e-02},
    {OrbitKind::ABC, 0.1833434647041659, 0.9074658265305127, 0.2832187403926303e-02},
};
// 434 points, precision 35.
const Orbit kRule434[] = {
    {OrbitKind::Vertex, 0, 0, 0.5265897968224436e-03},
    {OrbitKind::EdgeMidpoint, 0, 0, 0.2548219972002607e-02},
    {OrbitKind::FaceCentre, 0, 0, 0.2512317418927307e-02},
    {OrbitKind::AAB, 0.6909346307509111, 0, 0.2530403801186355e-02},
    {OrbitKind::AAB, 0.1774836054609158, 0, 0.2014279020918528e-02},
    {OrbitKind::AAB, 0.4914342637784746, 0, 0.2501725168402936e-02},
    {OrbitKind::AAB, 0.6456664707424256, 0, 0.2513267174597564e-02},
    {OrbitKind::AAB, 0.2861289010307638, 0, 0.2302694782227416e-02},
    {OrbitKind::AAB, 0.7568084367178018e-01, 0, 0.1462495621594614e-02},
    {OrbitKind::AAB, 0.3927259763368002, 0, 0.2445373437312980e-02},
    {OrbitKind::AB0, 0.8818132877794288, 0, 0.2417442375638981e-02},
    {OrbitKind::AB0, 0.9776428111182649, 0, 0.1910951282179532e-02},
    {OrbitKind::ABC, 0.2054823696403044, 0.8689460322872412, 0.2416930044324775e-02},
    {OrbitKind::ABC, 0.5905157048925271, 0.7999278543857286, 0.2512236854563495e-02},
    {OrbitKind::ABC, 0.5550152361076807, 0.7717462626915901, 0.2496644054553086e-02},
    {OrbitKind::ABC, 0.9371809858553722, 0.3344363145343455, 0.2236607760437849e-02},
};
// 590 points, precision 41.
const Orbit kRule590[] = {
    {OrbitKind::Vertex, 0, 0, 0.3095121295306187e-03},
    {OrbitKind::FaceCentre, 0, 0, 0.1852379698597489e-02},
    {OrbitKind::AAB, 0.7040954938227469, 0, 0.1871790639277744e-02},
    {OrbitKind::AAB, 0.6807744066455243, 0, 0.1858812585438317e-02},
    {OrbitKind::AAB, 0.6372546939258752, 0, 0.1852028828296213e-02},
    {OrbitKind::AAB, 0.5044419707800358, 0, 0.1846715956151242e-02},
    {OrbitKind::AAB, 0.4215761784010967, 0, 0.1818471778162769e-02},
    {OrbitKind::AAB, 0.3317920736472123, 0, 0.1749564657281154e-02},
    {OrbitKind::AAB, 0.2384736701421887, 0, 0.1617210647254411e-02},
    {OrbitKind::AAB, 0.1459036449157763, 0, 0.1384737234851692e-02},
    {OrbitKind::AAB, 0.6095034115507196e-01, 0, 0.9764331165051050e-03},
    {OrbitKind::AB0, 0.6116843442009876, 0, 0.1857161196774078e-02},
    {OrbitKind::AB0, 0.3964755348199858, 0, 0.1705153996395864e-02},
    {OrbitKind::AB0, 0.1724782009907724, 0, 0.1300321685886048e-02},
    {OrbitKind::ABC, 0.5610263808622060, 0.3518280927733519, 0.1842866472905286e-02},
    {OrbitKind::ABC, 0.4742392842551980, 0.2634716655937950, 0.1802658934377451e-02},
    {OrbitKind::ABC, 0.5984126497885380, 0.1816640840360209, 0.1849830560443660e-02},
    {OrbitKind::ABC, 0.3791035407695563, 0.1720795225656878, 0.1713904507106709e-02},
    {OrbitKind::ABC, 0.2778673190586244, 0.8213021581932511e-01, 0.1555213603396808e-02},
    {OrbitKind::ABC, 0.5033564271075117, 0.8999205842074875e-01, 0.1802239128008525e-02},
};
// 770 points, precision 47.
const Orbit kRule770[] = {
    {OrbitKind::Vertex, 0, 0, 0.2192942088181184e-03},
    {OrbitKind::EdgeMidpoint, 0, 0, 0.1436433617319080e-02},
    {OrbitKind::FaceCentre, 0, 0, 0.1421940344335877e-02},
    {OrbitKind::AAB, 0.5087204410502360e-01, 0, 0.6798123511050502e-03},
    {OrbitKind::AAB, 0.1228198790178831, 0, 0.9913184235294912e-03},
    {OrbitKind::AAB, 0.2026890814408786, 0, 0.1180207833238949e-02},
    {OrbitKind::AAB, 0.2847745156464294, 0, 0.1296599602080921e-02},
    {OrbitKind::AAB, 0.3656719078978026, 0, 0.1365871427428316e-02},
    {OrbitKind::AAB, 0.4428264886713469, 0, 0.1402988604775325e-02},
    {OrbitKind::AAB, 0.5140619627249735, 0, 0.1418645563595609e-02},
    {OrbitKind::AAB, 0.6306401219166803, 0, 0.1421376741851662e-02},
    {OrbitKind::AAB, 0.6716883332022612, 0, 0.1423996475490962e-02},
    {OrbitKind::AAB, 0.6979792685336881, 0, 0.1431554042178567e-02},
    {OrbitKind::AB0, 0.1446865674195309, 0, 0.9254401499865368e-03},
    {OrbitKind::AB0, 0.3390263475411216, 0, 0.1250239995053509e-02},
    {OrbitKind::AB0, 0.5335804651263506, 0, 0.1394365843329230e-02},
    {OrbitKind::ABC, 0.6944024393349413e-01, 0.2355187894242326, 0.1127089094671749e-02},
    {OrbitKind::ABC, 0.2269004109529460, 0.4102182474045730, 0.1345753760910670e-02},
    {OrbitKind::ABC, 0.8025574607775339e-01, 0.6214302417481605, 0.1424957283316783e-02},
    {OrbitKind::ABC, 0.1467999527896572, 0.3245284345717394, 0.1261523341237750e-02},
    {OrbitKind::ABC, 0.1571507769824727, 0.5224482189696630, 0.1392547106052696e-02},
    {OrbitKind::ABC, 0.2365702993157246, 0.6017546634089558, 0.1418761677877656e-02},
    {OrbitKind::ABC, 0.7714815866765732e-01, 0.4346575516141163, 0.1338366684479554e-02},
    {OrbitKind::ABC, 0.3062936666210730, 0.4908826589037616, 0.1393700862676131e-02},
    {OrbitKind::ABC, 0.3822477379524787, 0.5648768149099500, 0.1415914757466932e-02},
};
// 974 points, precision 53.
const Orbit kRule974[] = {
    {OrbitKind::Vertex, 0, 0, 0.1438294190527431e-03},
    {OrbitKind::FaceCentre, 0, 0, 0.1125772288287004e-02},
    {OrbitKind::AAB, 0.4292963545341347e-01, 0, 0.4948029341949241e-03},
    {OrbitKind::AAB, 0.1051426854086404, 0, 0.7357990109125470e-03},
    {OrbitKind::AAB, 0.1750024867623087, 0, 0.8889132771304384e-03},
    {OrbitKind::AAB, 0.2477653379650257, 0, 0.9888347838921435e-03},
    {OrbitKind::AAB, 0.3206567123955957, 0, 0.1053299681709471e-02},
    {OrbitKind::AAB, 0.3916520749849983, 0, 0.1092778807014578e-02},
    {OrbitKind::AAB, 0.4590825874187624, 0, 0.1114389394063227e-02},
    {OrbitKind::AAB, 0.5214563888415861, 0, 0.1123724788051555e-02},
    {OrbitKind::AAB, 0.6253170244654199, 0, 0.1125239325243814e-02},
    {OrbitKind::AAB, 0.6637926744523170, 0, 0.1126153271815905e-02},
    {OrbitKind::AAB, 0.6910410398498301, 0, 0.1130286931123841e-02},
    {OrbitKind::AAB, 0.7052907007457760, 0, 0.1134986534363955e-02},
    {OrbitKind::AB0, 0.1236686762657990, 0, 0.6823367927109931e-03},
    {OrbitKind::AB0, 0.2940777114468387, 0, 0.9454158160447096e-03},
    {OrbitKind::AB0, 0.4697753849207649, 0, 0.1074429975385679e-02},
    {OrbitKind::AB0, 0.6334563241139567, 0, 0.1129300086569132e-02},
    {OrbitKind::ABC, 0.5974048614181342e-01, 0.2029128752777523, 0.8436884500901954e-03},
    {OrbitKind::ABC, 0.1375760408473636, 0.4602621942484054, 0.1075255720448885e-02},
    {OrbitKind::ABC, 0.3391016526336286, 0.5030673999662036, 0.1108577236864462e-02},
    {OrbitKind::ABC, 0.1271675191439820, 0.2817606422442134, 0.9566475323783357e-03},
    {OrbitKind::ABC, 0.2693120740413512, 0.4331561291720157, 0.1080663250717391e-02},
    {OrbitKind::ABC, 0.1419786452601918, 0.6256167358580814, 0.1126797131196295e-02},
    {OrbitKind::ABC, 0.6709284600738255e-01, 0.3798395216859157, 0.1022568715358061e-02},
    {OrbitKind::ABC, 0.7057738183256172e-01, 0.5517505421423520, 0.1108960267713108e-02},
    {OrbitKind::ABC, 0.2783888477882155, 0.6029619156159187, 0.1122790653435766e-02},
    {OrbitKind::ABC, 0.1979578938917407, 0.3589606329589096, 0.1032401847117460e-02},
    {OrbitKind::ABC, 0.2087307061103274, 0.5348666438135476, 0.1107249382283854e-02},
    {OrbitKind::ABC, 0.4055122137872836, 0.5674997546074373, 0.1121780048519972e-02},
};
// 1202 points, precision 59.
const Orbit kRule1202[] = {
    {OrbitKind::Vertex, 0, 0, 0.1105189233267572e-03},
    {OrbitKind::EdgeMidpoint, 0, 0, 0.9205232738090741e-03},
    {OrbitKind::FaceCentre, 0, 0, 0.9133159786443561e-03},
    {OrbitKind::AAB, 0.3712636449657089e-01, 0, 0.3690421898017899e-03},
    {OrbitKind::AAB, 0.9140060412262223e-01, 0, 0.5603990928680660e-03},
    {OrbitKind::AAB, 0.1531077852469906, 0, 0.6865297629282609e-03},
    {OrbitKind::AAB, 0.2180928891660612, 0, 0.7720338551145630e-03},
    {OrbitKind::AAB, 0.2839874532200175, 0, 0.8301545958894795e-03},
    {OrbitKind::AAB, 0.3491177600963764, 0, 0.8686692550179628e-03},
    {OrbitKind::AAB, 0.4121431461444309, 0, 0.8927076285846890e-03},
    {OrbitKind::AAB, 0.4718993627149127, 0, 0.9060820238568219e-03},
    {OrbitKind::AAB, 0.5273145452842337, 0, 0.9119777254940867e-03},
    {OrbitKind::AAB, 0.6209475332444019, 0, 0.9128720138604181e-03},
    {OrbitKind::AAB, 0.6569722711857291, 0, 0.9130714935691735e-03},
    {OrbitKind::AAB, 0.6841788309070143, 0, 0.9152873784554116e-03},
    {OrbitKind::AAB, 0.7012604330123631, 0, 0.9187436274321654e-03},
    {OrbitKind::AB0, 0.1072382215478166, 0, 0.5176977312965694e-03},
    {OrbitKind::AB0, 0.2582068959496968, 0, 0.7331143682101417e-03},
    {OrbitKind::AB0, 0.4172752955306717, 0, 0.8463232836379928e-03},
    {OrbitKind::AB0, 0.5700366911792503, 0, 0.9031122694253992e-03},
    {OrbitKind::ABC, 0.9827986018263947, 0.1771774022615325, 0.6485778453163257e-03},
    {OrbitKind::ABC, 0.9624249230326228, 0.2475716463426288, 0.7435030910982369e-03},
    {OrbitKind::ABC, 0.9402007994128811, 0.3354616289066489, 0.7998527891839054e-03},
    {OrbitKind::ABC, 0.9320822040143202, 0.3173615246611977, 0.8101731497468018e-03},
    {OrbitKind::ABC, 0.9043674199393299, 0.4090268427085357, 0.8483389574594331e-03},
    {OrbitKind::ABC, 0.8912407560074747, 0.3854291150669224, 0.8556299257311812e-03},
    {OrbitKind::ABC, 0.8676435628462708, 0.4932221184851285, 0.8803208679738260e-03},
    {OrbitKind::ABC, 0.8581979986041619, 0.4785320675922435, 0.8811048182425720e-03},
    {OrbitKind::ABC, 0.8396753624049856, 0.4507422593157064, 0.8850282341265444e-03},
    {OrbitKind::ABC, 0.8165288564022188, 0.5632123020762100, 0.9021342299040653e-03},
    {OrbitKind::ABC, 0.8015469370783529, 0.5434303569693900, 0.9010091677105086e-03},
    {OrbitKind::ABC, 0.7773563069070351, 0.5123518486419871, 0.9022692938426915e-03},
    {OrbitKind::ABC, 0.7661621213900394, 0.6394279634749102, 0.9158016174693465e-03},
    {OrbitKind::ABC, 0.7553584143533510, 0.6269805509024392, 0.9131578003189435e-03},
    {OrbitKind::ABC, 0.7344305757559503, 0.6031161693096310, 0.9107813579482705e-03},
    {OrbitKind::ABC, 0.7043837184021765, 0.5693702498468441, 0.9105760258970126e-03},
};
const RuleTable kRules[] = {
    {6, 3, kRule6, sizeof(kRule6) / sizeof(Orbit)},
    {14, 5, kRule14, sizeof(kRule14) / sizeof(Orbit)},
    {26, 7, kRule26, sizeof(kRule26) / sizeof(Orbit)},
    {38, 9, kRule38, sizeof(kRule38) / sizeof(Orbit)},
    {50, 11, kRule50, sizeof(kRule50) / sizeof(Orbit)},
    {74, 13, kRule74, sizeof(kRule74) / sizeof(Orbit)},
    {86, 15, kRule86, sizeof(kRule86) / sizeof(Orbit)},
    {110, 17, kRule110, sizeof(kRule110) / sizeof(Orbit)},
    {146, 19, kRule146, sizeof(kRule146) / sizeof(Orbit)},
    {170, 21, kRule170, sizeof(kRule170) / sizeof(Orbit)},
    {194, 23, kRule194, sizeof(kRule194) / sizeof(Orbit)},
    {230, 25, kRule230, sizeof(kRule230) / sizeof(Orbit)},
    {266, 27, kRule266, sizeof(kRule266) / sizeof(Orbit)},
    {302, 29, kRule302, sizeof(kRule302) / sizeof(Orbit)},
    {350, 31, kRule350, sizeof(kRule350) / sizeof(Orbit)},
    {434, 35, kRule434, sizeof(kRule434) / sizeof(Orbit)},
    {590, 41, kRule590, sizeof(kRule590) / sizeof(Orbit)},
    {770, 47, kRule770, sizeof(kRule770) / sizeof(Orbit)},
    {974, 53, kRule974, sizeof(kRule974) / sizeof(Orbit)},
    {1202, 59, kRule1202, sizeof(kRule1202) / sizeof(Orbit)},
};

// All signed permutations of the base point (p, q, r), each once. Every orbit of O_h is of this
// form; duplicates (from zero or equal coordinates) are removed by exact comparison, which is
// exact here because duplicates are bitwise equal up to the sign of zero.
void appendOrbit(double p, double q, double r, double weight, std::size_t expectedSize, SphereQuadrature& rule) {
    const std::array<std::array<int, 3>, 6> permutations{
        {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
    const double base[3] = {p, q, r};
    const std::size_t first = rule.size();
    for (const auto& perm : permutations)
        for (int signs = 0; signs < 8; ++signs) {
            double c[3];
            for (int k = 0; k < 3; ++k) {
                c[k] = base[perm[k]] * ((signs >> k) & 1 ? -1.0 : 1.0);
                c[k] += 0.0;  // -0 -> +0, so equatorial points have z == +0 exactly
            }
            bool seen = false;
            for (std::size_t i = first; i < rule.size() && !seen; ++i)
                seen = rule.x[i] == c[0] && rule.y[i] == c[1] && rule.z[i] == c[2];
            if (seen) continue;
            rule.x.push_back(c[0]);
            rule.y.push_back(c[1]);
            rule.z.push_back(c[2]);
            rule.w.push_back(weight);
        }
    if (rule.size() - first != expectedSize)
        throw std::logic_error("Lebedev orbit generated " + std::to_string(rule.size() - first) +
                               " points instead of " + std::to_string(expectedSize));
}

SphereQuadrature buildRule(const RuleTable& table) {
    constexpr double fourPi = 4.0 * 3.14159265358979323846;
    SphereQuadrature rule;
    rule.precision = table.precision;
    rule.x.reserve(table.pointCount);
    rule.y.reserve(table.pointCount);
    rule.z.reserve(table.pointCount);
    rule.w.reserve(table.pointCount);
    for (std::size_t o = 0; o < table.orbitCount; ++o) {
        const Orbit& orbit = table.orbits[o];
        const double v = orbit.v * fourPi;
        switch (orbit.kind) {
            case OrbitKind::Vertex: appendOrbit(1.0, 0.0, 0.0, v, 6, rule); break;
            case OrbitKind::EdgeMidpoint: {
                const double s = std::sqrt(0.5);
                appendOrbit(0.0, s, s, v, 12, rule);
                break;
            }
            case OrbitKind::FaceCentre: {
                const double s = std::sqrt(1.0 / 3.0);
                appendOrbit(s, s, s, v, 8, rule);
                break;
            }
            case OrbitKind::AAB:
                appendOrbit(orbit.a, orbit.a, std::sqrt(1.0 - 2.0 * orbit.a * orbit.a), v, 24, rule);
                break;
            case OrbitKind::AB0: appendOrbit(orbit.a, std::sqrt(1.0 - orbit.a * orbit.a), 0.0, v, 24, rule); break;
            case OrbitKind::ABC:
                appendOrbit(orbit.a, orbit.b, std::sqrt(1.0 - orbit.a * orbit.a - orbit.b * orbit.b), v, 48, rule);
                break;
        }
    }
    if (static_cast<int>(rule.size()) != table.pointCount)
        throw std::logic_error("Lebedev rule " + std::to_string(table.pointCount) + " generated " +
                               std::to_string(rule.size()) + " points");
    return rule;
}

constexpr std::size_t kRuleCount = sizeof(kRules) / sizeof(RuleTable);

const std::vector<SphereQuadrature>& allRules() {
    // Built once (all rules together: about 5000 points, microseconds), thread-safe magic static.
    static const std::vector<SphereQuadrature> rules = [] {
        std::vector<SphereQuadrature> r;
        r.reserve(kRuleCount);
        for (const RuleTable& t : kRules) r.push_back(buildRule(t));
        return r;
    }();
    return rules;
}

std::size_t ruleSlot(int pointCount) {
    for (std::size_t i = 0; i < kRuleCount; ++i)
        if (kRules[i].pointCount == pointCount) return i;
    throw std::invalid_argument("no Lebedev rule with " + std::to_string(pointCount) + " points");
}

}  // namespace

const SphereQuadrature& lebedevRule(int pointCount) { return allRules()[ruleSlot(pointCount)]; }

std::vector<int> availableLebedevRules() {
    std::vector<int> counts;
    for (const RuleTable& t : kRules) counts.push_back(t.pointCount);
    return counts;
}

int lebedevPrecision(int pointCount) { return kRules[ruleSlot(pointCount)].precision; }

int lebedevPointCountForPrecision(int degree) {
    for (const RuleTable& t : kRules)
        if (t.precision >= degree) return t.pointCount;
    throw std::out_of_range("no Lebedev rule of precision " + std::to_string(degree) + " (maximum " +
                            std::to_string(kRules[kRuleCount - 1].precision) + ")");
}

HemisphereQuadrature hemisphereRule(int pointCount) {
    const SphereQuadrature& sphere = lebedevRule(pointCount);
    HemisphereQuadrature h;
    h.precision = sphere.precision;
    for (std::size_t i = 0; i < sphere.size(); ++i) {
        if (sphere.z[i] < 0.0) continue;
        // Equator points are shared by both hemispheres: half each (see the header for why exact).
        const double weight = sphere.z[i] == 0.0 ? 0.5 * sphere.w[i] : sphere.w[i];
        h.x.push_back(sphere.x[i]);
        h.y.push_back(sphere.y[i]);
        h.z.push_back(sphere.z[i]);
        h.w.push_back(weight);
    }
    return h;
}

}  // namespace rad
