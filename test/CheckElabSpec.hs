-- | The elaborated program (Stref.Checked): homes, initialisation lists,
-- explicit conversions, lines of the operations that can fail, and the
-- manual's example programs.
module CheckElabSpec (spec) where

import Control.Monad (forM_)
import qualified Data.IntMap.Strict as IM
import Data.List (sort)
import qualified Data.Text.IO as TIO
import Stref.Checked
import Stref.Operands
import Stref.Policy
import Stref.Syntax (Module (..), Program (..), VarBlock (..), VarSection (..))
import Stref.Syntax.Parser (parseModule)
import Stref.Types
import Stref.Values
import Support.Check
import System.Directory (listDirectory)
import System.FilePath (takeExtension, (</>))
import Test.Hspec

body :: CModule -> [CStmt]
body = cpBody . cmProgram

spec :: Spec
spec = describe "Check: elaboration" $ do
  -- program "..." puts the declarations on line 3 and the body on line 5
  let i = Var "I" (Basic INT) (Data 0)
      r = Var "R" (Basic REAL) (Data 1)
      u = Var "U" (Basic USINT) (Data 2)
      v = Var "V" (Array 1 3 INT) (Data 3)
      b = Var "B" (Basic BOOL) (Data 6)
      decls = "I : INT; R : REAL; U : USINT; V : ARRAY[1..3] OF INT; B : BOOL;"
      stmtOf src = body <$> elaborate (program decls src)

  describe "conversions become CConv nodes (MT-CONV-11)" $ do
    it "converts the INT operand of INT + REAL to REAL" $
      stmtOf "R := I + R;" `shouldReturn` [SAssign 5 (LTVar r) (CArith 5 OpAdd REAL (CConv INT REAL (CRead i)) (CRead r))]
    it "converts an assigned INT to REAL" $
      stmtOf "R := I;" `shouldReturn` [SAssign 5 (LTVar r) (CConv INT REAL (CRead i))]
    it "gives ANY_TO_BYTE of a REAL two steps, REAL -> DINT -> BYTE (MT-CONV-7)" $ do
      m <- elaborate (program "R : REAL; Y : BYTE;" "Y := ANY_TO_BYTE(R);")
      body m `shouldBe` [SAssign 5 (LTVar (Var "Y" (Basic BYTE) (Data 1))) (CConv DINT BYTE (CConv REAL DINT (CRead (Var "R" (Basic REAL) (Data 0)))))]
    it "makes ANY_TO_INT of an INT the identity (MT-CONV-8)" $
      stmtOf "I := ANY_TO_INT(I);" `shouldReturn` [SAssign 5 (LTVar i) (CRead i)]
    it "gives an explicit conversion its row" $
      stmtOf "I := REAL_TO_INT(R);" `shouldReturn` [SAssign 5 (LTVar i) (CConv REAL INT (CRead r))]
    it "converts a USINT index to DINT, and types a literal index DINT" $
      stmtOf "I := V[U]; V[2] := I;"
        `shouldReturn` [ SAssign 5 (LTVar i) (CReadIndex 5 v (CConv USINT DINT (CRead u)))
                       , SAssign 5 (LTIndex 5 v (CLit (VDInt 2))) (CRead i)
                       ]

  describe "literals and operators" $ do
    it "types a literal by the other operand: U > 200 compares USINTs" $
      stmtOf "B := U > 200;" `shouldReturn` [SAssign 5 (LTVar b) (CCompare OpGt USINT (CRead u) (CLit (VUSInt 200)))]
    it "types a literal-only expression by its context (A11)" $ do
      m <- elaborate (program "D : DINT;" "D := 2 + 3;")
      body m `shouldBe` [SAssign 5 (LTVar (Var "D" (Basic DINT) (Data 0))) (CArith 5 OpAdd DINT (CLit (VDInt 2)) (CLit (VDInt 3)))]
    it "types a literal-only comparison as INT when nothing else decides (A11)" $
      stmtOf "B := 1 < 70000;" `shouldReturn` [SAssign 5 (LTVar b) (CCompare OpLt DINT (CLit (VDInt 1)) (CLit (VDInt 70000)))]
    it "gives ANY_TO_REAL of a literal the smallest of INT, DINT, DWORD (A11)" $ do
      stmtOf "R := ANY_TO_REAL(5);" `shouldReturn` [SAssign 5 (LTVar r) (CConv INT REAL (CLit (VInt 5)))]
      stmtOf "R := ANY_TO_REAL(70000);" `shouldReturn` [SAssign 5 (LTVar r) (CConv DINT REAL (CLit (VDInt 70000)))]
      stmtOf "R := ANY_TO_REAL(3000000000);" `shouldReturn` [SAssign 5 (LTVar r) (CConv DWORD REAL (CLit (VDWord 3000000000)))]
    it "folds the sign into a real literal, keeping -0.0 (MT-LEX-19)" $ do
      stmtOf "R := -1.5;" `shouldReturn` [SAssign 5 (LTVar r) (CLit (VReal (-1.5)))]
      stmtOf "R := -0.0;" `shouldReturn` [SAssign 5 (LTVar r) (CLit (VReal (realFromBits 0x80000000)))]
    it "keeps a unary minus on a variable as a node with its line" $
      stmtOf "I := -I;" `shouldReturn` [SAssign 5 (LTVar i) (CNeg 5 INT (CRead i))]
    it "types EXPT by its base, the exponent USINT (MT-OP-20)" $
      stmtOf "I := EXPT(I, 2);" `shouldReturn` [SAssign 5 (LTVar i) (CExpt 5 INT (CRead i) (CLit (VUSInt 2)))]
    it "puts the division's line on the node (a multi-line statement)" $
      stmtOf "I :=\nI\n/ I;" `shouldReturn` [SAssign 5 (LTVar i) (CArith 7 OpDiv INT (CRead i) (CRead i))]
    it "chooses bitwise or logic by type (MT-OP-12)" $ do
      m <- elaborate (program "W : WORD; Y : BYTE;" "W := Y AND W;")
      let w = Var "W" (Basic WORD) (Data 0)
          y = Var "Y" (Basic BYTE) (Data 1)
      body m `shouldBe` [SAssign 5 (LTVar w) (CLogic OpAnd WORD (CConv BYTE WORD (CRead y)) (CRead w))]

  describe "statements" $ do
    it "gives FOR without BY the step 1 of the control type" $
      stmtOf "FOR U := 1 TO 5 DO I := U; END_FOR;"
        `shouldReturn` [SFor 5 u (CLit (VUSInt 1)) (CLit (VUSInt 5)) (CLit (VUSInt 1)) [SAssign 5 (LTVar i) (CConv USINT INT (CRead u))]]
    it "keeps the CASE labels as ranges and the ELSE" $
      stmtOf "CASE I OF 0: B := TRUE; 1, 2, 5..10: B := FALSE; ELSE B := TRUE; END_CASE;"
        `shouldReturn` [ SCase 5 (CRead i) [([(0, 0)], [SAssign 5 (LTVar b) (CLit (VBool True))]), ([(1, 1), (2, 2), (5, 10)], [SAssign 5 (LTVar b) (CLit (VBool False))])] [SAssign 5 (LTVar b) (CLit (VBool True))]
                       ]
    it "drops empty statements and keeps IF tests with their lines" $
      stmtOf ";\nIF B THEN ; ELSIF U = 0 THEN RETURN; END_IF;"
        `shouldReturn` [SIf [(6, CRead b, []), (6, CCompare OpEq USINT (CRead u) (CLit (VUSInt 0)), [SReturn 6])] []]
    it "binds the signals to their homes" $ do
      m <- elaborate (program "X : INT;" "OUTPUT2 := INPUT3;")
      body m `shouldBe` [SAssign 5 (LTVar (Var "OUTPUT2" (Basic BOOL) (SignalOutput 2))) (CRead (Var "INPUT3" (Basic BOOL) (SignalInput 3)))]

  describe "homes and initialisation" $ do
    let src =
          "VAR\nA : INT;\nVV : ARRAY[2..4] OF DINT := [1, 2, 3];\nM AT %M0010 : INT;\nM2 AT %M0011 : INT := 7;\nBB : BOOL;\nEND_VAR\n"
            <> "VAR CONSTANT K : INT := 4; END_VAR\n"
            <> "PROGRAM P\nVAR_INPUT X : REAL; END_VAR\nVAR Z : ARRAY[0..K] OF USINT; END_VAR\nZ[K] := 1;\nEND_PROGRAM\n"
        a = Var "A" (Basic INT) (Data 0)
        vv = Var "VV" (Array 2 4 DINT) (Data 1)
        mm = Var "M" (Basic INT) (Mapped (OpSimple KM 10))
        m2 = Var "M2" (Basic INT) (Mapped (OpSimple KM 11))
        bb = Var "BB" (Basic BOOL) (Data 4)
        k = Var "K" (Basic INT) (Data 5)
        x = Var "X" (Basic REAL) (Data 6)
        z = Var "Z" (Array 0 4 USINT) (Data 7)
    it "gives unmapped variables consecutive data slots, an array one per element" $ do
      m <- elaborate src
      map snd (cmNamed m) `shouldBe` [a, vv, mm, m2, bb, k, x, z]
      cmDataSize m `shouldBe` 12
    it "names globals G and program variables P.X" $ do
      m <- elaborate src
      map fst (cmNamed m) `shouldBe` ["A", "VV", "M", "M2", "BB", "K", "P.X", "P.Z"]
    it "initialises unmapped variables, and mapped ones only with an initialiser (A3)" $ do
      m <- elaborate src
      cmInits m
        `shouldBe` [ VarInit a Nothing
                   , VarInit vv (Just (InitArray [VDInt 1, VDInt 2, VDInt 3]))
                   , VarInit m2 (Just (InitScalar (VInt 7)))
                   , VarInit bb Nothing
                   , VarInit k (Just (InitScalar (VInt 4)))
                   , VarInit x Nothing
                   , VarInit z Nothing
                   ]
    it "lists every mapped variable" $ do
      m <- elaborate src
      cmMapped m `shouldBe` [mm, m2]
    it "counts the unmapped bytes (MT-LIM-10): 2 + 12 + 1 + 2 + 4 + 5" $ do
      m <- elaborate src
      cmDataBytes m `shouldBe` 26
    it "maps an array onto a table position" $ do
      m <- elaborate (program "T AT %TM0010[5] : ARRAY[1..3] OF INT;" "T[1] := 0;")
      map snd (cmNamed m) `shouldBe` [Var "T" (Array 1 3 INT) (Mapped (OpTablePos TM 10 5))]
    it "keeps a shadowed local's storage under global-wins (MT-SCOPE-6)" $ do
      m <- elaborate "VAR G : INT; END_VAR\nPROGRAM P\nVAR G : REAL; END_VAR\nG := 5;\nEND_PROGRAM\n"
      let g = Var "G" (Basic INT) (Data 0)
          pg = Var "G" (Basic REAL) (Data 1)
      cmNamed m `shouldBe` [("G", g), ("P.G", pg)]
      body m `shouldBe` [SAssign 4 (LTVar g) (CLit (VInt 5))]
    it "assigns the local under local-wins" $ do
      m <- elaborateWith mastertoolXE {pNameResolution = LocalWins} "VAR G : INT; END_VAR\nPROGRAM P\nVAR G : REAL; END_VAR\nG := 5;\nEND_PROGRAM\n"
      body m `shouldBe` [SAssign 4 (LTVar (Var "G" (Basic REAL) (Data 1))) (CLit (VReal 5))]
    it "sorts the program's parameters into inputs, in/outs and outputs" $ do
      m <- elaborate "PROGRAM P\nVAR_OUTPUT O : INT; END_VAR\nVAR_INPUT A : INT; END_VAR\nVAR_IN_OUT C : REAL; END_VAR\nO := A;\nEND_PROGRAM\n"
      let prog = cmProgram m
      (cpInputs prog, cpInOuts prog, cpOutputs prog)
        `shouldBe` ([Var "A" (Basic INT) (Data 1)], [Var "C" (Basic REAL) (Data 2)], [Var "O" (Basic INT) (Data 0)])

  describe "functions" $ do
    let src =
          "FUNCTION F0 : INT\nVAR_INPUT A : INT; END_VAR\nF0 := A;\nEND_FUNCTION\n"
            <> "FUNCTION F1 : REAL\nVAR_INPUT A : INT; C : REAL; END_VAR\nVAR L : ARRAY[0..1] OF INT; K : INT := 3; END_VAR\nF1 := C + A;\nEND_FUNCTION\n"
            <> "PROGRAM P\nVAR U : USINT; R : REAL; END_VAR\nR := F1(U, 2);\nEND_PROGRAM\n"
    -- lines: F0 on 1-4, F1 on 5-9 (its assignment on 8), the program from 10 (its call on 12)
    it "puts the result in frame slot 0, the parameters and locals after it" $ do
      m <- elaborate src
      let f1 = cmFunctions m IM.! 1
      cfName f1 `shouldBe` "F1"
      cfParams f1 `shouldBe` [Var "A" (Basic INT) (Frame 1), Var "C" (Basic REAL) (Frame 2)]
      cfLocals f1 `shouldBe` [VarInit (Var "L" (Array 0 1 INT) (Frame 3)) Nothing, VarInit (Var "K" (Basic INT) (Frame 5)) (Just (InitScalar (VInt 3)))]
      cfFrameSize f1 `shouldBe` 6
      cfBody f1 `shouldBe` [SAssign 8 (LTVar (Var "F1" (Basic REAL) (Frame 0))) (CArith 8 OpAdd REAL (CRead (Var "C" (Basic REAL) (Frame 2))) (CConv INT REAL (CRead (Var "A" (Basic INT) (Frame 1)))))]
    it "calls by function index, with converted arguments" $ do
      m <- elaborate src
      IM.keys (cmFunctions m) `shouldBe` [0, 1]
      body m `shouldBe` [SAssign 12 (LTVar (Var "R" (Basic REAL) (Data 1))) (CCall 12 1 REAL [CConv USINT INT (CRead (Var "U" (Basic USINT) (Data 0))), CLit (VReal 2)])]

  describe "the manual's example programs (test/examples)" $ do
    files <- runIO (sort . filter ((== ".st") . takeExtension) <$> listDirectory "test/examples")
    it "has example programs to check" $ files `shouldSatisfy` (not . null)
    forM_ files $ \f -> it ("accepts " <> f) $ do
      src <- TIO.readFile ("test/examples" </> f)
      -- examples whose program has parameters are F modules; the others are
      -- also valid P modules
      acceptsWith mastertoolXE FunctionModule src
      case parseModule mastertoolXE f src of
        Right md | all ((== SecVar) . vbSection) (prBlocks (modProgram md)) -> acceptsWith mastertoolXE ProcedureModule src
        _ -> pure ()
