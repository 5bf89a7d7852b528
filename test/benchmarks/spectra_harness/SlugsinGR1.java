// ltl_stack's harness: reads a .slugsin game and answers realizability with Spectra's C GR(1) solver
// (GR1GameImplC, CUDD 3.0 through spectra-cudd), with the IDE's default options ("all": decomposed
// transitions with a quantification schedule, fixpoint recycling, early exits, dynamic reordering).
import java.io.*;
import java.lang.management.ManagementFactory;
import java.nio.file.*;
import java.util.*;
import net.sf.javabdd.BDD;
import tau.smlab.syntech.gamemodel.GameModel;
import tau.smlab.syntech.jtlv.env.module.ModuleBDDField;
import tau.smlab.syntech.gamemodel.PlayerModule;
import tau.smlab.syntech.gamemodel.PlayerModule.TransFuncType;
import tau.smlab.syntech.games.gr1.GR1GameExperiments;
import tau.smlab.syntech.games.gr1.GR1GameImplC;
import tau.smlab.syntech.jtlv.BDDPackage;
import tau.smlab.syntech.jtlv.Env;

public class SlugsinGR1 {
  static Map<String, ModuleBDDField> fields = new HashMap<>();

  static long cpu() {
    return ((com.sun.management.OperatingSystemMXBean) ManagementFactory.getOperatingSystemMXBean()).getProcessCpuTime();
  }

  static BDD atom(String tok) {
    boolean primed = tok.endsWith("'");
    String name = primed ? tok.substring(0, tok.length() - 1) : tok;
    ModuleBDDField f = fields.get(name);
    if (f == null) throw new IllegalArgumentException("unknown variable " + name);
    return (primed ? f.getOtherDomain() : f.getDomain()).ithVar(1);
  }

  static int pos;
  static String[] toks;
  static List<BDD> memo;

  static BDD parse() {
    String t = toks[pos++];
    switch (t) {
      case "1": return Env.TRUE();
      case "0": return Env.FALSE();
      case "!": return parse().not();
      case "&": { BDD a = parse(); BDD b = parse(); return a.andWith(b); }
      case "|": { BDD a = parse(); BDD b = parse(); return a.orWith(b); }
      case "^": { BDD a = parse(); BDD b = parse(); return a.xorWith(b); }
      case "?": return memo.get(Integer.parseInt(toks[pos++])).id();
      case "$": {
        int n = Integer.parseInt(toks[pos++]);
        List<BDD> saved = memo;
        memo = new ArrayList<>();
        for (int i = 0; i < n; i++) memo.add(parse());
        BDD last = memo.get(n - 1).id();
        for (BDD b : memo) b.free();
        memo = saved;
        return last;
      }
      default: return atom(t);
    }
  }

  static BDD formula(String line) {
    toks = line.trim().split("\\s+");
    pos = 0;
    memo = new ArrayList<>();
    BDD b = parse();
    if (pos != toks.length) throw new IllegalArgumentException("trailing tokens in: " + line);
    return b;
  }

  public static void main(String[] args) throws Exception {
    long start = cpu();
    Map<String, List<String>> sec = new LinkedHashMap<>();
    String cur = null;
    for (String line : Files.readAllLines(Paths.get(args[0]))) {
      String s = line.trim();
      if (s.isEmpty() || s.startsWith("#")) continue;
      if (s.startsWith("[")) { cur = s; sec.putIfAbsent(cur, new ArrayList<>()); continue; }
      sec.get(cur).add(s);
    }
    BDDPackage.setCurrPackage(BDDPackage.CUDD, BDDPackage.BBDPackageVersion.CUDD_3_0);
    Env.enableReorder();
    GR1GameExperiments.DETECT_FIX_POINT_EARLY = true;
    GR1GameExperiments.USE_FIXPOINT_RECYCLE = true;
    GR1GameExperiments.STOP_WHEN_INITIALS_LOST = true;
    GR1GameExperiments.SIMULTANEOUS_CONJUNCTION_ABSTRACTION = true;
    long ready = cpu();
    PlayerModule env = new PlayerModule();
    env.setName("env");
    PlayerModule sys = new PlayerModule();
    sys.setName("sys");
    for (String v : sec.getOrDefault("[INPUT]", List.of())) fields.put(v, env.addVar(v, false));
    for (String v : sec.getOrDefault("[OUTPUT]", List.of())) fields.put(v, sys.addVar(v, false));
    env.setTransFuncType(TransFuncType.DECOMPOSED_FUNC);
    sys.setTransFuncType(TransFuncType.DECOMPOSED_FUNC);
    env.addToTransList(env.trans().id());
    sys.addToTransList(sys.trans().id());
    sys.addToPartTransList(sys.trans().id());
    for (String f : sec.getOrDefault("[ENV_INIT]", List.of())) env.conjunctInitial(formula(f));
    for (String f : sec.getOrDefault("[SYS_INIT]", List.of())) sys.conjunctInitial(formula(f));
    for (String f : sec.getOrDefault("[ENV_TRANS]", List.of())) { BDD b = formula(f); env.conjunctTrans(b.id()); env.addToTransList(b); }
    for (String f : sec.getOrDefault("[SYS_TRANS]", List.of())) { BDD b = formula(f); sys.conjunctTrans(b.id()); sys.addToTransList(b); }
    for (String f : sec.getOrDefault("[ENV_LIVENESS]", List.of())) env.addJustice(formula(f));
    for (String f : sec.getOrDefault("[SYS_LIVENESS]", List.of())) sys.addJustice(formula(f));
    if (env.justiceNum() == 0) env.addJustice(Env.TRUE());
    if (sys.justiceNum() == 0) sys.addJustice(Env.TRUE());
    env.calcTransQuantList();
    sys.calcTransQuantList();
    GameModel model = new GameModel();
    model.setEnv(env);
    model.setSys(sys);
    long built = cpu();
    PrintStream out = System.out;
    System.setOut(new PrintStream(OutputStream.nullOutputStream()));
    boolean realizable = new GR1GameImplC(model).checkRealizability();
    long solved = cpu();
    System.setOut(out);
    System.out.printf("{\"realizable\": %b, \"startup\": %.3f, \"build\": %.3f, \"solve\": %.3f, \"cpu\": %.3f}%n",
        realizable, (ready - start) / 1e9, (built - ready) / 1e9, (solved - built) / 1e9, (solved - ready) / 1e9);
  }
}
